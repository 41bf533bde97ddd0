#include "kernels/point_set.hpp"
#include "kernels/mpu_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "kernels/errors.hpp"
#include "kernels/field_input.hpp"
#include "kernels/partition_of_unity.hpp"

namespace meshless {
namespace {

constexpr int kMaxStack = 512;

struct OctreeBuilder {
    const std::vector<Vec3>& pos;
    std::uint32_t max_pts, min_pts, max_depth;
    double alpha;
    struct NodeRec {
        Vec3 c;
        double half, r, rsub;
        std::int32_t child, local;
    };
    std::vector<NodeRec> nodes{};
    std::vector<std::uint32_t> flat{};                       // leaf point lists, DFS order
    std::vector<std::pair<std::uint64_t, std::uint32_t>> leaf_range{};  // (first, count) per local
    std::vector<std::pair<std::int32_t, const std::vector<std::uint32_t>*>> path{};  // ancestors and their points
    std::vector<std::pair<double, std::uint32_t>> near{};
    std::uint64_t grown = 0, capped = 0;
    std::uint32_t depth_reached = 0;

    double radius_of(double half) const { return alpha * 2.0 * std::sqrt(3.0) * half; }

    void build(std::int32_t node, const std::vector<std::uint32_t>& cand, std::uint32_t depth) {
        depth_reached = std::max(depth_reached, depth);
        const Vec3 c = nodes[node].c;
        const double r = nodes[node].r;
        const double r2 = r * r;
        std::vector<std::uint32_t> inside;
        for (std::uint32_t i : cand) {
            const Vec3 e = pos[i] - c;
            if (dot(e, e) <= r2) inside.push_back(i);
        }
        if (inside.size() > max_pts && depth < max_depth) {
            const std::int32_t first = static_cast<std::int32_t>(nodes.size());
            nodes[node].child = first;
            const double h = nodes[node].half * 0.5;
            for (int q = 0; q < 8; ++q) {
                NodeRec ch;
                ch.c = c + Vec3{(q & 1) ? h : -h, (q & 2) ? h : -h, (q & 4) ? h : -h};
                ch.half = h;
                ch.r = radius_of(h);
                ch.rsub = 0;
                ch.child = -1;
                ch.local = -1;
                nodes.push_back(ch);
            }
            path.emplace_back(node, &inside);
            for (int q = 0; q < 8; ++q) build(first + q, inside, depth + 1);
            path.pop_back();
            return;
        }
        // Leaf.
        const std::uint64_t first = flat.size();
        if (inside.size() > max_pts) {  // depth limit: keep the nearest max_pts
            near.clear();
            for (std::uint32_t i : inside) {
                const Vec3 e = pos[i] - c;
                near.emplace_back(dot(e, e), i);
            }
            std::nth_element(near.begin(), near.begin() + max_pts, near.end());
            std::vector<std::uint32_t> keep;
            for (std::uint32_t k = 0; k < max_pts; ++k) keep.push_back(near[k].second);
            std::sort(keep.begin(), keep.end());
            inside.swap(keep);
            ++capped;
        } else if (inside.size() < min_pts && !path.empty()) {
            // Grow the sphere to hold min_pts points, searching the nearest ancestor whose sphere
            // is guaranteed to contain the grown one (the root contains every point).
            for (std::size_t a = path.size(); a-- > 0;) {
                const std::vector<std::uint32_t>& list = *path[a].second;
                if (list.size() < min_pts && a > 0) continue;
                near.clear();
                for (std::uint32_t i : list) {
                    const Vec3 e = pos[i] - c;
                    near.emplace_back(dot(e, e), i);
                }
                const std::size_t k = std::min<std::size_t>(min_pts, near.size()) - 1;
                std::nth_element(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(k), near.end());
                const double rk = std::sqrt(near[k].first) * (1 + 1e-9) + 1e-300;
                const double rnew = std::max(r, rk);
                const NodeRec& an = nodes[path[a].first];
                if (a > 0 && rnew + norm(an.c - c) > an.r) continue;
                const double rn2 = rnew * rnew;
                inside.clear();
                for (const auto& [d2, i] : near)
                    if (d2 <= rn2) inside.push_back(i);
                std::sort(inside.begin(), inside.end());
                nodes[node].r = rnew;
                ++grown;
                break;
            }
        }
        nodes[node].local = static_cast<std::int32_t>(leaf_range.size());
        leaf_range.emplace_back(first, static_cast<std::uint32_t>(inside.size()));
        flat.insert(flat.end(), inside.begin(), inside.end());
    }
};

}  // namespace

MpuField::MpuField(const PointSet& points, const FieldParams& params, FieldBuildStats* stats) {
    if (params.mpu_max_points < 8) throw UsageError("mpu: N (mpu_max_points) must be >= 8");
    if (params.mpu_min_points < 1 || params.mpu_min_points > params.mpu_max_points)
        throw UsageError("mpu: mpu_min_points must be in 1..N");
    if (!(params.mpu_alpha > 0.5) || !std::isfinite(params.mpu_alpha))
        throw UsageError("mpu: alpha must be > 0.5 (the sphere must cover its cube)");
    if (params.mpu_max_depth < 1 || params.mpu_max_depth > 60) throw UsageError("mpu: mpu_max_depth must be in 1..60");
    FieldBuildStats local_stats;
    FieldBuildStats& st = stats ? *stats : local_stats;
    MergedPoints mp = prepare_field_points(points, params, "mpu", &st);
    origin_ = mp.origin;
    scale_ = mp.scale;
    bounds_ = points.bounds();
    pos_ = std::move(mp.pos);
    const std::vector<double>& val = mp.value;
    const double c = hardy_c_world_for(params, bounds_);

    const auto [lo, hi] = bounding_box(pos_);
    const Vec3 w = hi - lo;
    const double wmax = std::max({w.x, w.y, w.z});
    OctreeBuilder b{pos_, params.mpu_max_points, params.mpu_min_points, params.mpu_max_depth, params.mpu_alpha, {}, {}, {}, {}, {}};
    OctreeBuilder::NodeRec root;
    root.c = (lo + hi) * 0.5;
    root.half = wmax > 0 ? 0.5 * wmax * (1 + 1e-9) : 1.0;
    root.r = b.radius_of(root.half);
    root.rsub = 0;
    root.child = -1;
    root.local = -1;
    b.nodes.push_back(root);
    {
        std::vector<std::uint32_t> all(pos_.size());
        for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<std::uint32_t>(i);
        b.build(0, all, 0);
    }
    if (b.flat.size() > 0xFFFFFFF0ull) throw UsageError("mpu: too many local points (" + std::to_string(b.flat.size()) + ")");

    nodes_.resize(b.nodes.size());
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const auto& r = b.nodes[i];
        nodes_[i] = Node{r.c, r.half, r.r, r.r, r.child, r.local};
    }
    for (std::size_t i = nodes_.size(); i-- > 0;) {  // children follow their parent
        Node& nd = nodes_[i];
        if (nd.child < 0) { nd.rsub = nd.r; continue; }
        double rs = 0;
        for (int q = 0; q < 8; ++q) {
            const Node& ch = nodes_[static_cast<std::size_t>(nd.child + q)];
            rs = std::max(rs, norm(ch.c - nd.c) + ch.rsub);
        }
        nd.rsub = rs;
    }
    idx_ = std::move(b.flat);
    lambda_.assign(idx_.size(), 0.0);
    locals_.resize(b.leaf_range.size());
    for (std::size_t l = 0; l < locals_.size(); ++l) locals_[l].first = static_cast<std::uint32_t>(b.leaf_range[l].first);

    std::vector<MultiquadricOutcome> outcome(locals_.size());
    std::vector<std::uint8_t> rank_def(locals_.size(), 0);
    tbb::enumerable_thread_specific<MultiquadricSolver> solvers;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, locals_.size(), 16), [&](const tbb::blocked_range<std::size_t>& r) {
        MultiquadricSolver& solver = solvers.local();
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            MultiquadricLocal& h = locals_[l];
            const std::uint32_t cnt = b.leaf_range[l].second;
            const MultiquadricFitResult res =
                solver.fit(pos_, val, std::span<const std::uint32_t>(idx_.data() + h.first, cnt), c, h,
                           std::span<double>(lambda_.data() + h.first, cnt));
            outcome[l] = res.outcome;
            rank_def[l] = res.poly_rank < 4;
        }
    });

    st.locals = locals_.size();
    st.grown = b.grown;
    st.capped = b.capped;
    st.octree_nodes = nodes_.size();
    st.octree_depth = b.depth_reached;
    std::uint64_t sum = 0;
    for (std::size_t l = 0; l < locals_.size(); ++l) {
        st.interpolated += outcome[l] == MultiquadricOutcome::interpolated;
        st.regularised += outcome[l] == MultiquadricOutcome::regularised;
        st.linear_fallback += outcome[l] == MultiquadricOutcome::linear_fallback;
        st.polynomial_only += outcome[l] == MultiquadricOutcome::polynomial_only;
        st.rank_deficient += rank_def[l];
        sum += b.leaf_range[l].second;
        st.max_local_points = std::max<std::uint64_t>(st.max_local_points, b.leaf_range[l].second);
    }
    st.mean_local_points = locals_.empty() ? 0.0 : static_cast<double>(sum) / static_cast<double>(locals_.size());
    st.memory_bytes = pos_.size() * sizeof(Vec3) + nodes_.size() * sizeof(Node) +
                      locals_.size() * sizeof(MultiquadricLocal) + idx_.size() * (sizeof(std::uint32_t) + sizeof(double));
}

std::vector<MpuField::LeafInfo> MpuField::leaves() const {
    std::vector<LeafInfo> out;
    for (const Node& n : nodes_)
        if (n.child < 0) out.push_back({Vec3{n.c.x / scale_.x, n.c.y / scale_.y, n.c.z / scale_.z} + origin_, n.half, n.r});
    return out;
}

void MpuField::evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const {
    PuBlend blend;
    const bool want_grad = !grad.empty();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::array<std::int32_t, kMaxStack> stack;
    for (std::size_t t = 0; t < p.size(); ++t) {
        const Vec3 dw = p[t] - origin_;
        const Vec3 x{dw.x * scale_.x, dw.y * scale_.y, dw.z * scale_.z};
        blend.reset();
        if (std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z)) {
            int top = 0;
            stack[top++] = 0;
            while (top > 0) {
                const Node& nd = nodes_[static_cast<std::size_t>(stack[--top])];
                const Vec3 e = x - nd.c;
                if (!(dot(e, e) < nd.rsub * nd.rsub)) continue;
                if (nd.child >= 0) {
                    for (int q = 7; q >= 0; --q) stack[top++] = nd.child + q;
                    continue;
                }
                double d;
                if (!PuBlend::covers(x, nd.c, nd.r, &d)) continue;
                Vec3 gq;
                const double q = multiquadric_evaluate(locals_[static_cast<std::size_t>(nd.local)], pos_.data(),
                                                       idx_.data(), lambda_.data(), x, want_grad ? &gq : nullptr);
                blend.add(x, nd.c, nd.r, d, q, gq);
            }
        }
        value[t] = blend.finish(want_grad ? &grad[t] : nullptr);
        if (want_grad) grad[t] = {grad[t].x * scale_.x, grad[t].y * scale_.y, grad[t].z * scale_.z};
        (void)nan;
    }
}

}  // namespace meshless
