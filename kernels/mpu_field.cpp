#include "kernels/point_set.hpp"
#include "kernels/mpu_field.hpp"

#include <atomic>
#include "kernels/flat_hull.hpp"
#include "kernels/local_multiquadric_fit.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <functional>
#include <type_traits>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "kernels/errors.hpp"
#include "kernels/field_input.hpp"
#include "kernels/batch_order.hpp"
#include "kernels/partition_of_unity.hpp"

namespace meshless {
namespace {

constexpr int kMaxStack = 512;

// The octree of section 5.5, depth first. Subtrees of nodes whose sphere holds at least
// kParallelPoints points are built in parallel (oneTBB), each by a builder of its own, and
// appended to the parent's arrays in child order: the nodes, leaves and point lists come out in
// exactly the order of a sequential depth-first build, for any thread count.
constexpr std::size_t kParallelPoints = 8192;

/// The most points a flat leaf reads from one ancestor's list when it looks for points off its
/// plane (kernels/flat_hull.hpp): 64 full leaves.
constexpr std::size_t kSpanPoints = 64 * 140;

/// A region build's boxes in frame units (kernels/field_region.hpp): the queries it answers and the
/// points it was given (shrunk by the merge tolerance: a point there merged as in the whole set).
struct RegionBoxes {
    Vec3 qlo, qhi, llo, lhi;
    double reach;  // a subtree's blend spheres lie within its node cube grown by reach x the node's half edge
    // whether the subtree of the cube (c, half) can weigh at a query
    bool reaches(const Vec3& c, double half) const {
        const double m = half * (1 + reach);
        return c.x + m >= qlo.x && c.x - m <= qhi.x && c.y + m >= qlo.y && c.y - m <= qhi.y && c.z + m >= qlo.z && c.z - m <= qhi.z;
    }
    // whether every point of the whole set inside the sphere (c, r) was given
    bool holds(const Vec3& c, double r) const {
        return c.x - r >= llo.x && c.x + r <= lhi.x && c.y - r >= llo.y && c.y + r <= lhi.y && c.z - r >= llo.z && c.z + r <= lhi.z;
    }
    // FieldRegion::missing and ::present for frame spheres (null: unknown)
    std::function<std::uint64_t(const Vec3&, double)> missing_in, present_in;
};

struct OctreeBuilder {
    const std::vector<Vec3>& pos;
    std::uint32_t max_pts, min_pts, max_depth;
    double alpha;
    double blend_alpha;  // a leaf's blend sphere: blend_alpha x its diagonal (<= its fit sphere)
    bool data_flat;  // every point in one plane or line: no leaf can find a point off its plane
    const RegionBoxes* region;  // null: the whole set; else subtrees that cannot weigh at a query are pruned
    struct NodeRec {
        Vec3 c;
        double half, r, rsub;
        std::int32_t child, local;
    };
    struct Ancestor {
        Vec3 c;
        double r;                                   // its sphere (an inner node's never changes)
        const std::vector<std::uint32_t>* points;  // the points inside it
    };
    std::vector<NodeRec> nodes{};
    std::vector<std::uint32_t> flat{};                       // leaf point lists, DFS order
    std::vector<std::pair<std::uint64_t, std::uint32_t>> leaf_range{};  // (first, count) per local
    std::vector<Ancestor> path{};                            // ancestors, root first
    std::vector<std::pair<double, std::uint32_t>> near{};
    std::vector<double> d2s{}, sel{};  // squared distances in list order, and a copy to select from
    std::uint64_t grown = 0, capped = 0, spanned = 0, pruned = 0;
    std::uint32_t depth_reached = 0;
    bool inexact = false;  // a list this region build read may lack points of the whole set

    // At least the whole set's points inside the sphere (c, r) that this build was not given (0:
    // its list is the whole set's; a whole-set build: always 0).
    std::uint64_t missing(const Vec3& c, double r) const {
        if (!region || region->holds(c, r)) return 0;
        if (!region->missing_in) return std::numeric_limits<std::uint32_t>::max();
        return region->missing_in(c, r);
    }
    // At least the whole set's points inside the sphere (c, r) (a region build's lower bound; 0
    // when unknown or held: the list's own count then decides).
    std::uint64_t present(const Vec3& c, double r) const {
        if (!region || !region->present_in || region->holds(c, r)) return 0;
        return region->present_in(c, r);
    }
    // A decision or list that holds for the whole set only when `exact`.
    // (the ball (c, r), frame units, whose points it needs: collected for the caller to load)
    std::vector<std::pair<Vec3, double>> lacking{};
    void need(bool exact, const Vec3& c, double r) {
        if (exact) return;
        inexact = true;
        lacking.emplace_back(c, r);
    }

    double radius_of(double half) const { return alpha * 2.0 * std::sqrt(3.0) * half; }

    // d2s = the squared distances from c of the points of `list`, in list order.
    void distances(const std::vector<std::uint32_t>& list, const Vec3& c) {
        d2s.resize(list.size());
        for (std::size_t j = 0; j < list.size(); ++j) {
            const Vec3 e = pos[list[j]] - c;
            d2s[j] = dot(e, e);
        }
    }
    // The (k+1)-th smallest of d2s (k < d2s.size()): a selection over the distances alone, which
    // moves 8-byte keys where one over (distance, index) pairs moved 16 and compared the index on
    // ties; the value is the same. guess2 > 0: a squared distance that likely holds more than k of
    // them: the selection then runs over those alone (the same (k+1)-th smallest when more than k
    // are at most guess2; else over all).
    double kth_distance(std::size_t k, double guess2 = 0) {
        std::size_t m = 0;
        if (guess2 > 0) {  // (branch-free: whether a point passes is not predictable)
            sel.resize(d2s.size());
            for (double d2 : d2s) {
                sel[m] = d2;
                m += d2 <= guess2;
            }
            sel.resize(m);
        }
        if (m <= k) sel.assign(d2s.begin(), d2s.end());
        std::nth_element(sel.begin(), sel.begin() + static_cast<std::ptrdiff_t>(k), sel.end());
        return sel[k];
    }
    // The points of `list` with d2s <= r2, in list order (ascending when the list is).
    void within(const std::vector<std::uint32_t>& list, double r2, std::vector<std::uint32_t>& out) const {
        out.clear();
        for (std::size_t j = 0; j < list.size(); ++j)
            if (d2s[j] <= r2) out.push_back(list[j]);
    }

    // Appends the subtree built by `sub` (its node 0 is this builder's node `at`) in DFS order and
    // frees sub's arrays (the point lists are held twice only for the subtree being appended).
    void append(std::int32_t at, OctreeBuilder& sub) {
        const std::int32_t base = static_cast<std::int32_t>(nodes.size()) - 1;  // sub's node i >= 1 -> base + i
        const std::int32_t lbase = static_cast<std::int32_t>(leaf_range.size());
        const std::uint64_t fbase = flat.size();
        auto moved = [&](NodeRec n) {
            if (n.child >= 0) n.child += base;
            if (n.local >= 0) n.local += lbase;
            return n;
        };
        nodes[static_cast<std::size_t>(at)] = moved(sub.nodes[0]);
        for (std::size_t i = 1; i < sub.nodes.size(); ++i) nodes.push_back(moved(sub.nodes[i]));
        for (const auto& [first, count] : sub.leaf_range) leaf_range.emplace_back(first + fbase, count);
        if (flat.empty()) flat.swap(sub.flat);
        else flat.insert(flat.end(), sub.flat.begin(), sub.flat.end());
        std::vector<std::uint32_t>().swap(sub.flat);
        std::vector<NodeRec>().swap(sub.nodes);
        grown += sub.grown;
        spanned += sub.spanned;
        capped += sub.capped;
        pruned += sub.pruned;
        inexact = inexact || sub.inexact;
        lacking.insert(lacking.end(), sub.lacking.begin(), sub.lacking.end());
        depth_reached = std::max(depth_reached, sub.depth_reached);
    }

    // The points of `cand` inside the sphere of each of the 8 children of `first` (one pass over
    // cand, which each child's own pass read again: 10^6 points, 1 thread, octree 4.9 -> 3.1 s).
    std::array<std::vector<std::uint32_t>, 8> split(std::int32_t first, const std::vector<std::uint32_t>& cand) const {
        std::array<std::vector<std::uint32_t>, 8> in;
        Vec3 c[8];
        for (int q = 0; q < 8; ++q) {
            c[q] = nodes[static_cast<std::size_t>(first + q)].c;
            in[static_cast<std::size_t>(q)].reserve(cand.size() / 4);
        }
        const double r = nodes[static_cast<std::size_t>(first)].r;  // the same for the 8 (same half edge)
        const double r2 = r * r;
        // child q's centre takes coordinate (q & 1, q & 2, q & 4) of two per axis, so the six squared
        // axis offsets make the eight squared distances: (dx^2 + dy^2) + dz^2, the bits of dot(e, e)
        // (no contraction: -ffp-contract=off), where each child took three subtractions and products
        const double cx[2] = {c[0].x, c[1].x}, cy[2] = {c[0].y, c[2].y}, cz[2] = {c[0].z, c[4].z};
        for (std::uint32_t i : cand) {
            const Vec3 p = pos[i];
            const double sx[2] = {(p.x - cx[0]) * (p.x - cx[0]), (p.x - cx[1]) * (p.x - cx[1])};
            const double sy[2] = {(p.y - cy[0]) * (p.y - cy[0]), (p.y - cy[1]) * (p.y - cy[1])};
            const double sz[2] = {(p.z - cz[0]) * (p.z - cz[0]), (p.z - cz[1]) * (p.z - cz[1])};
            for (int q = 0; q < 8; ++q)
                if ((sx[q & 1] + sy[(q >> 1) & 1]) + sz[(q >> 2) & 1] <= r2) in[static_cast<std::size_t>(q)].push_back(i);
        }
        return in;
    }

    // Builds `node` from the points inside its sphere (ascending indices).
    void build(std::int32_t node, std::vector<std::uint32_t> inside, std::uint32_t depth) {
        depth_reached = std::max(depth_reached, depth);
        const Vec3 c = nodes[node].c;
        const double r = nodes[node].r;
        if (region && depth > 0 && !region->reaches(c, nodes[node].half)) {  // weighs at no query: no local
            nodes[node].r = 0;
            ++pruned;
            return;
        }
        // (a region build: a sphere past the loaded points whose cells surely hold more than N
        // points is split as the whole set's is)
        if ((inside.size() > max_pts || (region && inside.size() <= max_pts && present(c, r) > max_pts)) && depth < max_depth) {
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
            path.push_back(Ancestor{c, r, &inside});
            std::array<std::vector<std::uint32_t>, 8> in = split(first, inside);
            if (inside.size() >= kParallelPoints) {
                std::vector<OctreeBuilder> sub;
                sub.reserve(8);
                for (int q = 0; q < 8; ++q) {
                    sub.push_back(OctreeBuilder{pos, max_pts, min_pts, max_depth, alpha, blend_alpha, data_flat, region, {}, {}, {}, path, {}});
                    sub.back().nodes.push_back(nodes[static_cast<std::size_t>(first + q)]);
                }
                tbb::parallel_for(0, 8, [&](int q) { sub[q].build(0, std::move(in[static_cast<std::size_t>(q)]), depth + 1); });
                for (int q = 0; q < 8; ++q) append(first + q, sub[q]);
            } else {
                for (int q = 0; q < 8; ++q) build(first + q, std::move(in[static_cast<std::size_t>(q)]), depth + 1);
            }
            path.pop_back();
            return;
        }
        // Leaf. A region build checks every decision and list against the points it lacks (need):
        // counts compared with a threshold hold when the missing points cannot cross it, a list of
        // nearest points when its ball lacks none.
        const std::uint64_t missing_here = missing(c, r);
        if (depth < max_depth) need(inside.size() + missing_here <= max_pts, c, r);
        const std::uint64_t first = flat.size();
        bool leaf_grown = false;
        if (inside.size() > max_pts) {  // depth limit: keep the nearest max_pts
            need(missing_here == 0, c, r);
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
        } else if (inside.size() > min_pts && blend_alpha < alpha) {
            // The fit takes the points of the blend sphere, or the nearest min_pts when it holds
            // fewer: every point where the local weighs is still interpolated, and a fit costs
            // about min_pts^3 however dense the data (the whole fit sphere held up to N points:
            // 8x the work of a min_pts fit, and the points beyond the blend sphere never weigh).
            const double rb = std::min(r, blend_alpha * 2.0 * std::sqrt(3.0) * nodes[node].half);
            distances(inside, c);
            std::size_t held = 0;
            for (double d2 : d2s) held += d2 <= rb * rb;
            double rfit = rb;
            if (held < min_pts) rfit = std::max(rb, std::sqrt(kth_distance(min_pts - 1)) * (1 + 1e-9) + 1e-300);
            need(missing(c, rfit) == 0, c, rfit);
            std::vector<std::uint32_t> keep;
            keep.reserve(std::max<std::size_t>(held, min_pts));
            within(inside, rfit * rfit, keep);  // (ascending: inside is)
            inside.swap(keep);
            nodes[node].r = rfit;
        } else if (inside.size() < min_pts && !path.empty()) {
            // Grow the sphere to hold min_pts points, searching the nearest ancestor whose sphere
            // is guaranteed to contain the grown one (the root contains every point).
            need(inside.size() + missing_here < min_pts, c, r);
            for (std::size_t a = path.size(); a-- > 0;) {
                const std::vector<std::uint32_t>& list = *path[a].points;
                const std::uint64_t missing_a = missing(path[a].c, path[a].r);
                if (list.size() < min_pts && a > 0) {
                    need(list.size() + missing_a < min_pts, path[a].c, path[a].r);
                    continue;
                }
                distances(list, c);
                const std::size_t k = std::min<std::size_t>(min_pts, list.size()) - 1;
                // the guess: 1.5 x the (k+1)-th neighbour's distance were the ancestor's points even
                const double guess = 1.5 * path[a].r * std::cbrt(static_cast<double>(k + 1) / static_cast<double>(list.size()));
                const double rk = std::sqrt(kth_distance(k, guess * guess)) * (1 + 1e-9) + 1e-300;
                if (list.size() < min_pts) need(missing_a == 0, path[a].c, path[a].r);
                else need(missing(c, rk) == 0, c, rk);
                const double rnew = std::max(r, rk);
                if (a > 0 && rnew + norm(path[a].c - c) > path[a].r) continue;
                within(list, rnew * rnew, inside);  // (ascending: the ancestor's list is)
                nodes[node].r = rnew;
                leaf_grown = true;
                break;
            }
        } else {
            need(missing_here == 0, c, r);  // the list as it is (a count at min_pts could be higher)
        }
        // A flat leaf (coplanar or collinear points: layers or grid planes farther apart than the
        // leaves) also takes the nearest points off its plane or line, from the nearest ancestor
        // that holds enough (kernels/flat_hull.hpp): its linear part is then determined across it.
        if (inside.size() >= 2 && !path.empty() && !data_flat) {
            PointMoments mo;
            mo.ref = pos[inside.front()];  // (a data point: exact zeros along a plane of the data)
            for (std::uint32_t i : inside) mo.add(pos[i] - mo.ref);
            if (const std::optional<FlatHull> h = flat_hull(mo)) {
                const std::uint32_t extra = std::max<std::uint32_t>(4, min_pts / 2);
                // the nearest ancestor holding `extra` points off the hull; climbing stops before a
                // list of more than kSpanPoints points (a bounded scan; the parent's is always read)
                for (std::size_t a = path.size(); a-- > 0;) {
                    near.clear();
                    for (std::uint32_t i : *path[a].points)
                        if (h->off(pos[i])) near.emplace_back(dot(pos[i] - c, pos[i] - c), i);
                    const std::uint64_t missing_a = near.size() < extra ? missing(path[a].c, path[a].r) : 0;
                    if (a > 0 && path[a - 1].points->size() <= kSpanPoints)
                        need(path[a - 1].points->size() + missing(path[a - 1].c, path[a - 1].r) <= kSpanPoints, path[a - 1].c, path[a - 1].r);
                    if (near.size() < extra && a > 0 && path[a - 1].points->size() <= kSpanPoints) {
                        need(near.size() + missing_a < extra, path[a].c, path[a].r);
                        continue;
                    }
                    const std::size_t take = std::min<std::size_t>(extra, near.size());
                    std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(take), near.end());
                    if (near.size() < extra) need(missing_a == 0, path[a].c, path[a].r);
                    else if (take > 0) {
                        const double rt = std::sqrt(near[take - 1].first) * (1 + 1e-9);
                        need(missing(c, rt) == 0, c, rt);
                    }
                    for (std::size_t q = 0; q < take; ++q) inside.push_back(near[q].second);
                    std::sort(inside.begin(), inside.end());
                    inside.erase(std::unique(inside.begin(), inside.end()), inside.end());
                    leaf_grown = leaf_grown || take > 0;
                    spanned += take > 0;
                    break;
                }
            }
        }
        grown += leaf_grown;  // (once, whether grown for mpu_min_points, spanned or both)
        nodes[node].local = static_cast<std::int32_t>(leaf_range.size());
        leaf_range.emplace_back(first, static_cast<std::uint32_t>(inside.size()));
        flat.insert(flat.end(), inside.begin(), inside.end());
    }
};

}  // namespace

MpuField::MpuField(const PointSet& points, const FieldParams& params, FieldBuildStats* stats,
                   const FieldProgress& progress, const FitShare* share, const FieldRegion* region, MpuFitCache* cache) {
    if (params.mpu_max_points < 8) throw InvalidArgument("mpu: N (mpu_max_points) must be >= 8");
    if (params.mpu_min_points < 1 || params.mpu_min_points > params.mpu_max_points)
        throw InvalidArgument("mpu: mpu_min_points must be in 1..N");
    if (!(params.mpu_alpha > 0.5) || !std::isfinite(params.mpu_alpha))
        throw InvalidArgument("mpu: alpha must be > 0.5 (the sphere must cover its cube)");
    if (!(params.mpu_blend_alpha > 0.5) || !std::isfinite(params.mpu_blend_alpha))
        throw InvalidArgument("mpu: blend alpha must be > 0.5 (the blend sphere must cover its cube)");
    if (params.mpu_max_depth < 1 || params.mpu_max_depth > 60) throw InvalidArgument("mpu: mpu_max_depth must be in 1..60");
    FieldBuildStats local_stats;
    FieldBuildStats& st = stats ? *stats : local_stats;
    // The whole set's frame (origin, scales, root cube, Hardy's c, merge tolerance, flatness): a
    // region build takes it from the caller, so that it builds the same tree over its part.
    const FieldFrame frame = region ? region->frame : field_frame_of(points.pos);
    MergedPoints mp = prepare_field_points(points, params, "mpu", &st, frame);
    origin_ = mp.origin;
    scale_ = mp.scale;
    bounds_ = frame.bounds;
    const double c = hardy_c_world_for(params, bounds_);
    const auto [lo, hi] = frame_box(mp, frame.bounds);  // (the points' frame bounding box, bit for bit)
    morton_order_points(mp, lo, hi);  // cache-friendly node lists and fits
    const std::vector<Vec3> pts = std::move(mp.pos);
    const std::vector<double>& val = mp.value;
    std::optional<RegionBoxes> boxes;
    if (region) {
        const auto q = frame_box(mp, region->query), l = frame_box(mp, region->loaded);
        const double shrink = 2 * mp.tolerance * std::max({scale_.x, scale_.y, scale_.z});
        const Vec3 sv{shrink, shrink, shrink};
        boxes = RegionBoxes{q[0], q[1], l[0] + sv, l[1] - sv, params.mpu_blend_alpha * 2.0 * std::sqrt(3.0), {}, {}};
        // frame sphere -> world: a ball around (missing) or inside (present) the ellipsoid it is
        const Vec3 o = origin_, sc = scale_;
        const double smin = std::min({sc.x, sc.y, sc.z}), smax = std::max({sc.x, sc.y, sc.z});
        const auto world = [o, sc](const Vec3& c) { return Vec3{c.x / sc.x + o.x, c.y / sc.y + o.y, c.z / sc.z + o.z}; };
        if (region->missing)
            boxes->missing_in = [world, smin, &m = region->missing](const Vec3& c, double r) { return m(world(c), r / smin * (1 + 1e-9)); };
        if (region->present)
            boxes->present_in = [world, smax, &p = region->present](const Vec3& c, double r) { return p(world(c), r / smax * (1 - 1e-9)); };
        region_ = true;
    }

    const Vec3 w = hi - lo;
    const double wmax = std::max({w.x, w.y, w.z});
    OctreeBuilder b{pts, params.mpu_max_points, params.mpu_min_points, params.mpu_max_depth, params.mpu_alpha,
                    params.mpu_blend_alpha, frame.data_flat, boxes ? &*boxes : nullptr, {}, {}, {}, {}, {}};
    OctreeBuilder::NodeRec root;
    root.c = (lo + hi) * 0.5;
    root.half = wmax > 0 ? 0.5 * wmax * (1 + 1e-9) : 1.0;
    root.r = b.radius_of(root.half);
    root.rsub = 0;
    root.child = -1;
    root.local = -1;
    b.nodes.push_back(root);
    {
        std::vector<std::uint32_t> inside;  // the root's sphere holds every point (radius > half diagonal): tested all the same
        const double r2 = root.r * root.r;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const Vec3 e = pts[i] - root.c;
            if (dot(e, e) <= r2) inside.push_back(static_cast<std::uint32_t>(i));
        }
        b.build(0, std::move(inside), 0);
    }
    if (b.flat.size() > 0xFFFFFFF0ull) throw InvalidArgument("mpu: too many local points (" + std::to_string(b.flat.size()) + ")");
    pruned_ = b.pruned;
    region_exact_ = !b.inexact;
    if (region) {  // the balls to load, in world units (a ball around the frame ellipsoid)
        const double smin = std::min({scale_.x, scale_.y, scale_.z});
        for (const auto& [fc, fr] : b.lacking)
            lacking_.push_back({Vec3{fc.x / scale_.x + origin_.x, fc.y / scale_.y + origin_.y, fc.z / scale_.z + origin_.z}, fr / smin * (1 + 1e-9)});
    }
    // the fitted field's heap as the octree decides it (the lookup grid, about one cell a leaf, aside)
    const std::uint64_t field_bytes = b.nodes.size() * sizeof(Node) + b.leaf_range.size() * (sizeof(MultiquadricLocal) + sizeof(LeafSphere)) +
                                      b.flat.size() * 4 * sizeof(double);
    over_budget_ = region && region->max_field_bytes > 0 && field_bytes > region->max_field_bytes;
    if (!region_exact_ || over_budget_) {  // the caller builds again: no fits (most of the build's time)
        st.octree_nodes = b.nodes.size();
        st.octree_depth = b.depth_reached;
        st.locals = b.leaf_range.size();
        st.memory_bytes = field_bytes;
        return;
    }

    nodes_.resize(b.nodes.size());
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const auto& r = b.nodes[i];
        // a leaf blends over its blend sphere (inside its fit sphere r.r)
        const double rr = r.child < 0 ? std::min(r.r, params.mpu_blend_alpha * 2.0 * std::sqrt(3.0) * r.half) : r.r;
        nodes_[i] = Node{r.c, r.half, rr, rr, r.child, r.local};
    }
    compute_subtree_radii();
    const std::vector<std::uint32_t> idx = std::move(b.flat);
    lambda_.assign(idx.size(), 0.0);
    locals_.resize(b.leaf_range.size());
    for (std::size_t l = 0; l < locals_.size(); ++l) locals_[l].first = static_cast<std::uint32_t>(b.leaf_range[l].first);

    std::vector<MultiquadricOutcome> outcome(locals_.size());
    std::vector<std::uint8_t> rank_def(locals_.size(), 0);
    const bool shared = share && share->ranks > 1;
    const auto range_of = [&](int r) {  // rank r's locals
        const std::size_t n = locals_.size(), k = static_cast<std::size_t>(share->ranks);
        return std::pair<std::size_t, std::size_t>{n * static_cast<std::size_t>(r) / k, n * static_cast<std::size_t>(r + 1) / k};
    };
    const std::pair<std::size_t, std::size_t> fits = shared ? range_of(share->rank) : std::pair<std::size_t, std::size_t>{0, locals_.size()};
    const std::size_t fit0 = fits.first, fit1 = fits.second;
    if (shared) cache = nullptr;
    std::vector<std::int32_t> leaf_node;  // (a cache: each local's octree node, and its key)
    std::vector<MpuFitCache::Key> keys;
    std::atomic<std::uint64_t> reused{0};
    if (cache) {
        leaf_node.assign(locals_.size(), -1);
        for (std::size_t i = 0; i < b.nodes.size(); ++i)
            if (b.nodes[i].local >= 0) leaf_node[static_cast<std::size_t>(b.nodes[i].local)] = static_cast<std::int32_t>(i);
        keys.resize(locals_.size());
    }
    tbb::enumerable_thread_specific<MultiquadricSolver> solvers;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(fit0, fit1, 16), [&](const tbb::blocked_range<std::size_t>& r) {
        MultiquadricSolver& solver = solvers.local();
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            MultiquadricLocal& h = locals_[l];
            const std::uint32_t cnt = b.leaf_range[l].second;
            const std::span<const std::uint32_t> mine(idx.data() + h.first, cnt);
            if (cache) {
                const auto& nd = b.nodes[static_cast<std::size_t>(leaf_node[l])];
                keys[l] = MpuFitCache::key_of(nd.c, nd.half, pts, val, mine);
                if (const MpuFitCache::Fit* f = cache->find(keys[l])) {
                    const std::uint32_t first = h.first;
                    h = f->local;
                    h.first = first;
                    std::copy(f->lambda.begin(), f->lambda.end(), lambda_.begin() + first);
                    outcome[l] = f->outcome;
                    rank_def[l] = f->flags;
                    reused.fetch_add(1, std::memory_order_relaxed);
                    continue;
                }
            }
            const LocalFitResult res = fit_local_multiquadric(solver, pts, val, mine, c, params, h, std::span<double>(lambda_.data() + h.first, cnt));
            outcome[l] = res.fit.outcome;
            rank_def[l] = static_cast<std::uint8_t>((res.fit.poly_rank < 4 ? 1 : 0) | (res.refitted ? 2 : 0));  // (shared with the ranks)
        }
        if (progress) progress(static_cast<double>(r.size()), static_cast<double>(fit1 - fit0));
    });
    if (shared) gather_fits(*share, range_of, outcome, rank_def);
    if (cache) {  // keep the fits the next region may meet (the reach its own build prunes with)
        cache->count_hits(reused.load());
        const double reach = params.mpu_blend_alpha * 2.0 * std::sqrt(3.0);
        for (std::size_t l = 0; l < locals_.size(); ++l) {
            const auto& nd = b.nodes[static_cast<std::size_t>(leaf_node[l])];
            if (!cache->keeps((nd.c.z - nd.half * (1 + reach)) / scale_.z + origin_.z, (nd.c.z + nd.half * (1 + reach)) / scale_.z + origin_.z))
                continue;
            const MultiquadricLocal& h = locals_[l];
            MpuFitCache::Fit f{h, std::vector<double>(lambda_.begin() + h.first, lambda_.begin() + h.first + b.leaf_range[l].second),
                               outcome[l], rank_def[l]};
            cache->keep(keys[l], std::move(f));
        }
    }

    // Centres copied structure-of-arrays in leaf order (the lambda order): leaf l's run is
    // [first, first + count) of px_/py_/pz_ and of lambda_.
    px_.resize(idx.size());
    py_.resize(idx.size());
    pz_.resize(idx.size());
    for (std::size_t k = 0; k < idx.size(); ++k) {
        px_[k] = pts[idx[k]].x;
        py_[k] = pts[idx[k]].y;
        pz_[k] = pts[idx[k]].z;
    }
    build_lookup();

    st.locals = locals_.size();
    st.grown = b.grown;
    st.spanned = b.spanned;
    st.capped = b.capped;
    st.octree_nodes = nodes_.size();
    st.octree_depth = b.depth_reached;
    std::uint64_t sum = 0;
    for (std::size_t l = 0; l < locals_.size(); ++l) {
        st.interpolated += outcome[l] == MultiquadricOutcome::interpolated;
        st.regularised += outcome[l] == MultiquadricOutcome::regularised;
        st.linear_fallback += outcome[l] == MultiquadricOutcome::linear_fallback;
        st.polynomial_only += outcome[l] == MultiquadricOutcome::polynomial_only;
        st.rank_deficient += (rank_def[l] & 1) != 0;
        st.refitted += (rank_def[l] & 2) != 0;
        st.c_lowered += locals_[l].c2 < c * c;
        st.mean_local_c += std::sqrt(locals_[l].c2);
        sum += b.leaf_range[l].second;
        st.max_local_points = std::max<std::uint64_t>(st.max_local_points, b.leaf_range[l].second);
    }
    st.mean_local_points = locals_.empty() ? 0.0 : static_cast<double>(sum) / static_cast<double>(locals_.size());
    st.mean_local_c = locals_.empty() ? 0.0 : st.mean_local_c / static_cast<double>(locals_.size());
    st.memory_bytes = nodes_.size() * sizeof(Node) + locals_.size() * (sizeof(MultiquadricLocal) + sizeof(LeafSphere)) +
                      lambda_.size() * 4 * sizeof(double) + (grid_first_.size() + grid_leaf_.size()) * sizeof(std::uint32_t);
}

void MpuField::gather_fits(const FitShare& share, const std::function<std::pair<std::size_t, std::size_t>(int)>& range_of,
                           std::vector<MultiquadricOutcome>& outcome, std::vector<std::uint8_t>& rank_def) {
    // A rank's bytes: its locals, outcomes, rank flags, then its lambdas (contiguous in local order).
    const auto lambda_at = [&](std::size_t l) { return l < locals_.size() ? locals_[l].first : lambda_.size(); };
    const auto bytes_of = [&](std::size_t l0, std::size_t l1) {
        return (l1 - l0) * (sizeof(MultiquadricLocal) + sizeof(MultiquadricOutcome) + 1) + (lambda_at(l1) - lambda_at(l0)) * sizeof(double);
    };
    // (the lambda range from this rank's own octree, taken before a received local overwrites its start)
    const auto fields = [&](std::size_t l0, std::size_t l1, auto&& visit) {
        const std::size_t lam0 = lambda_at(l0), lam1 = lambda_at(l1);
        visit(static_cast<void*>(locals_.data() + l0), (l1 - l0) * sizeof(MultiquadricLocal));
        visit(static_cast<void*>(outcome.data() + l0), (l1 - l0) * sizeof(MultiquadricOutcome));
        visit(static_cast<void*>(rank_def.data() + l0), l1 - l0);
        visit(static_cast<void*>(lambda_.data() + lam0), (lam1 - lam0) * sizeof(double));
    };
    static_assert(std::is_trivially_copyable_v<MultiquadricLocal>);
    const auto [m0, m1] = range_of(share.rank);
    std::vector<std::byte> mine(bytes_of(m0, m1));
    std::byte* to = mine.data();
    fields(m0, m1, [&](void* f, std::size_t n) {
        std::memcpy(to, f, n);
        to += n;
    });
    const std::vector<std::byte> all = share.allgather(mine);
    std::size_t at = 0;
    for (int r = 0; r < share.ranks; ++r) {
        const auto [l0, l1] = range_of(r);
        const std::size_t n = bytes_of(l0, l1);
        if (all.size() - at < n)
            throw FormatError("mpu: the ranks' shared fits hold " + std::to_string(all.size()) + " bytes, rank " + std::to_string(r) +
                              "'s range ends at byte " + std::to_string(at + n));
        if (r != share.rank) {
            // the octree is every rank's own: a local's start must be the one this rank computed
            std::vector<std::uint32_t> firsts(l1 - l0);
            for (std::size_t l = l0; l < l1; ++l) firsts[l - l0] = locals_[l].first;
            const std::byte* from = all.data() + at;
            fields(l0, l1, [&](void* f, std::size_t n) {
                std::memcpy(f, from, n);
                from += n;
            });
            for (std::size_t l = l0; l < l1; ++l)
                if (locals_[l].first != firsts[l - l0] ||
                    locals_[l].count > (l + 1 < l1 ? firsts[l + 1 - l0] : lambda_at(l1)) - firsts[l - l0])
                    throw FormatError("mpu: rank " + std::to_string(r) + " fitted local " + std::to_string(l) +
                                      " over other points than this rank's octree gives it");
        }
        at += n;
    }
    if (at != all.size())
        throw FormatError("mpu: the ranks' shared fits hold " + std::to_string(all.size()) + " bytes, " + std::to_string(at) + " expected");
}

std::vector<MpuField::LeafInfo> MpuField::leaves() const {
    std::vector<LeafInfo> out(locals_.size());
    for (const Node& n : nodes_)
        if (n.child < 0 && n.local >= 0)
            out[static_cast<std::size_t>(n.local)] = {Vec3{n.c.x / scale_.x, n.c.y / scale_.y, n.c.z / scale_.z} + origin_, n.half, n.r};
    return out;
}

void MpuField::compute_subtree_radii() {
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
}

int MpuField::lookup_level(std::size_t per_leaf_cells) const {
    // the finest power-of-two grid with at most per_leaf_cells x (number of leaves) cells, level <= 7
    int level = 0;
    const std::size_t cap = std::max<std::size_t>(1, locals_.size()) * per_leaf_cells;
    while (level < 7 && (std::size_t{1} << (3 * (level + 1))) <= cap) ++level;
    return level;
}

void MpuField::lookup_geometry(int level) {
    // Leaf spheres in leaf order; a uniform grid of 2^level cells a side over the root cube.
    leaf_.resize(locals_.size());
    for (const Node& nd : nodes_)
        if (nd.child < 0 && nd.local >= 0) leaf_[static_cast<std::size_t>(nd.local)] = LeafSphere{nd.c, nd.r, nd.r * nd.r};
    const Node& root = nodes_[0];
    g_ = std::int64_t{1} << level;
    g_lo_ = root.c - Vec3{root.half, root.half, root.half};
    g_cell_ = 2 * root.half / static_cast<double>(g_);
    g_inv_ = 1 / g_cell_;
}

namespace {
// The lookup cells [lo, hi] (per axis, clamped to the grid of g cells a side) that a leaf sphere's
// bounding box overlaps; lo > hi when none. Clamped in double first: a sphere far larger than the
// grid (a hostile .mlf) must not overflow the integer conversion. Finite values whose sums overflow
// (inf - inf, or inf times a zero inverse cell size) give a NaN bound, which std::clamp would pass
// on to the conversion (undefined): the axis is then taken whole, so the leaf is listed wherever
// it might reach and the exact sphere test decides (build_lookup coarsens a grid that gets too
// much work).
void lookup_range(const Vec3& c, double r, const Vec3& grid_lo, double inv, std::int64_t g, std::int64_t lo[3],
                  std::int64_t hi[3]) {
    const double top = static_cast<double>(g);
    for (int a = 0; a < 3; ++a) {
        const double l = std::floor((c[a] - r - grid_lo[a]) * inv), h = std::floor((c[a] + r - grid_lo[a]) * inv);
        if (std::isnan(l) || std::isnan(h)) {
            lo[a] = 0;
            hi[a] = g - 1;
            continue;
        }
        lo[a] = static_cast<std::int64_t>(std::clamp(l, 0.0, top));
        hi[a] = static_cast<std::int64_t>(std::clamp(h, -1.0, top - 1));
    }
}
}  // namespace

std::uint64_t MpuField::lookup_work(std::int64_t g) const {
    const double inv = static_cast<double>(g) / (2 * nodes_[0].half);
    std::uint64_t total = 0;
    for (const LeafSphere& s : leaf_) {
        std::int64_t lo[3], hi[3];
        lookup_range(s.c, s.r, g_lo_, inv, g, lo, hi);
        std::uint64_t v = 1;
        for (int a = 0; a < 3; ++a) v *= static_cast<std::uint64_t>(std::max<std::int64_t>(0, hi[a] - lo[a] + 1));
        total += v;  // <= 2^21 cells per leaf (level <= 7): no overflow below 2^43 leaves
    }
    return total;
}

void MpuField::lookup_lists(std::int64_t g, std::vector<std::uint32_t>& first, std::vector<std::uint32_t>& list) const {
    // Per cell of a g^3 grid over the root cube, the leaves whose sphere meets the cell (ascending).
    const std::size_t ncell = static_cast<std::size_t>(g * g * g);
    const std::uint64_t work = lookup_work(g);
    if (work > kLookupWorkPerCell * (ncell + leaf_.size()) || work > std::numeric_limits<std::uint32_t>::max())
        throw InvalidArgument("mpu field: " + std::to_string(leaf_.size()) + " leaf spheres cover " + std::to_string(work) +
                              " cells of a " + std::to_string(g) + "^3 lookup grid (spheres far larger than their leaves)");
    const double cell = 2 * nodes_[0].half / static_cast<double>(g), inv = 1 / cell;
    auto meets = [&](const LeafSphere& s, std::int64_t i, std::int64_t j, std::int64_t k) {
        const std::int64_t ci[3] = {i, j, k};
        double d2 = 0;
        for (int a = 0; a < 3; ++a) {
            const double b0 = g_lo_[a] + static_cast<double>(ci[a]) * cell, b1 = b0 + cell;
            const double e = s.c[a] < b0 ? b0 - s.c[a] : s.c[a] > b1 ? s.c[a] - b1 : 0.0;
            d2 += e * e;
        }
        return d2 <= s.r2 * (1 + 1e-9);
    };
    first.assign(ncell + 1, 0);
    std::vector<std::uint32_t> fill;
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            for (std::size_t c = 0; c < ncell; ++c) first[c + 1] += first[c];  // <= work < 2^32
            list.resize(first[ncell]);
            fill.assign(first.begin(), first.end() - 1);
        }
        for (std::size_t l = 0; l < leaf_.size(); ++l) {
            std::int64_t lo[3], hi[3];
            lookup_range(leaf_[l].c, leaf_[l].r, g_lo_, inv, g, lo, hi);
            for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
                for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
                    for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
                        if (!meets(leaf_[l], i, j, k)) continue;
                        const std::size_t c = static_cast<std::size_t>(i + g * (j + g * k));
                        if (pass == 0) ++first[c + 1];
                        else list[fill[c]++] = static_cast<std::uint32_t>(l);
                    }
        }
    }
}

void MpuField::build_lookup() {
    // About kLookupCellsPerLeaf cells per leaf; coarser while the leaves' spheres would cover more
    // than kLookupWorkPerCell x (cells + leaves) cells (never for a fitted field, whose blend spheres
    // are ~1 leaf cube: a .mlf with huge radii gets the one-cell grid, correct and slow, not a hang)
    int level = lookup_level(kLookupCellsPerLeaf);
    lookup_geometry(level);  // leaf_ and g_lo_, which lookup_work reads, do not depend on the level
    const auto too_much = [&](int lv) {
        const std::uint64_t g = std::uint64_t{1} << lv;
        return lookup_work(static_cast<std::int64_t>(g)) > kLookupWorkPerCell * (g * g * g + leaf_.size());
    };
    if (level > 0 && too_much(level)) {
        while (level > 0 && too_much(level)) --level;
        lookup_geometry(level);
    }
    lookup_lists(g_, grid_first_, grid_leaf_);
}

inline void MpuField::add_leaf(std::size_t l, const Vec3& x, EvalScratch& sc) const {
    const LeafSphere& s = leaf_[l];
    const Vec3 e = x - s.c;
    const double d2 = dot(e, e);
    if (d2 < s.r2) {
        sc.leaf.push_back(static_cast<std::uint32_t>(l));
        sc.dist.push_back(d2);
    }
}

void MpuField::select_leaves(const std::uint32_t* cand, std::size_t n, const Vec3& x, EvalScratch& sc) const {
    // branch-free: about a third of the candidates pass, in no predictable pattern
    sc.leaf.resize(n);
    sc.dist.resize(n);
    std::size_t m = 0;
    for (std::size_t q = 0; q < n; ++q) {
        const std::uint32_t l = cand[q];
        const LeafSphere& s = leaf_[l];
        const Vec3 e = x - s.c;
        const double d2 = dot(e, e);
        sc.leaf[m] = l;
        sc.dist[m] = d2;
        m += d2 < s.r2;
    }
    sc.leaf.resize(m);
    sc.dist.resize(m);
}

void MpuField::blend_leaves(const Vec3& x, bool want_grad, EvalScratch& sc, PuBlend& blend) const {
    const std::size_t n = sc.leaf.size();
    sc.runs.resize(n);
    sc.terms.resize(n);
    sc.sums.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const MultiquadricLocal& h = locals_[sc.leaf[i]];
        // the first lines of its centres and coefficients: the misses of all the leaves overlap
        __builtin_prefetch(px_.data() + h.first);
        __builtin_prefetch(py_.data() + h.first);
        __builtin_prefetch(pz_.data() + h.first);
        __builtin_prefetch(lambda_.data() + h.first);
        sc.runs[i] = MqRun{h.first, h.count};
        sc.dist[i] = std::sqrt(sc.dist[i]);  // the squared distance until here
    }
    for (std::size_t i = 0; i < n; ++i) {
        const MultiquadricLocal& h = locals_[sc.leaf[i]];
        sc.terms[i] = MqLocalTerms{&sc.runs[i], h.count > 0 ? 1u : 0u, lambda_.data() + h.first, h.c2};
    }
    multiquadric_sums(px_.data(), py_.data(), pz_.data(), sc.terms, x, want_grad, sc.sums.data());
    for (std::size_t i = 0; i < n; ++i) {
        const MultiquadricLocal& h = locals_[sc.leaf[i]];
        const LeafSphere& s = leaf_[sc.leaf[i]];
        const MqSum& acc = sc.sums[i];
        const double q = h.a0 + dot(h.a, x - h.origin) + acc.v;
        blend.add(x, s.c, s.r, sc.dist[i], q, want_grad ? h.a + Vec3{acc.gx, acc.gy, acc.gz} : h.a);
    }
}

std::uint32_t MpuField::batch_key(const Vec3& pw) const {
    const Vec3 dw = pw - origin_;
    const double u[3] = {(dw.x * scale_.x - g_lo_.x) * g_inv_, (dw.y * scale_.y - g_lo_.y) * g_inv_,
                         (dw.z * scale_.z - g_lo_.z) * g_inv_};
    const double top = static_cast<double>(g_);
    if (!(u[0] >= 0 && u[0] < top && u[1] >= 0 && u[1] < top && u[2] >= 0 && u[2] < top)) return 0xFFFFFFFFu;
    return morton_key(static_cast<std::uint32_t>(u[0]), static_cast<std::uint32_t>(u[1]), static_cast<std::uint32_t>(u[2]));
}

void MpuField::evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const {
    if (!region_exact_ || over_budget_) throw InvalidArgument("mpu: a region build that lacked points or memory has no fits to evaluate");
    PuBlend blend;
    EvalScratch sc;
    const bool want_grad = !grad.empty();
    for_each_in_key_order(p.size(), [&](std::size_t t) { return batch_key(p[t]); },
                          [&](std::size_t t) { eval_one(p[t], value[t], want_grad ? &grad[t] : nullptr, blend, sc); },
                          [&](std::size_t t) {
                              __builtin_prefetch(&p[t]);
                              __builtin_prefetch(&value[t], 1);
                              if (want_grad) __builtin_prefetch(&grad[t], 1);
                          });
}

void MpuField::find_leaves(const Vec3& x, EvalScratch& sc) const {
    const double u[3] = {(x.x - g_lo_.x) * g_inv_, (x.y - g_lo_.y) * g_inv_, (x.z - g_lo_.z) * g_inv_};
    const double top = static_cast<double>(g_);
    if (u[0] >= 0 && u[0] < top && u[1] >= 0 && u[1] < top && u[2] >= 0 && u[2] < top) {
        // inside the root cube: the leaves listed for x's lookup cell
        const std::size_t c = static_cast<std::size_t>(static_cast<std::int64_t>(u[0]) +
                                                       g_ * (static_cast<std::int64_t>(u[1]) +
                                                             g_ * static_cast<std::int64_t>(u[2])));
        select_leaves(grid_leaf_.data() + grid_first_[c], grid_first_[c + 1] - grid_first_[c], x, sc);
        return;
    }
    // outside: descend the tree (spheres reach beyond the root cube)
    std::array<std::int32_t, kMaxStack> stack;
    int top_ = 0;
    stack[top_++] = 0;
    while (top_ > 0) {
        const Node& nd = nodes_[static_cast<std::size_t>(stack[--top_])];
        const Vec3 e = x - nd.c;
        if (!(dot(e, e) < nd.rsub * nd.rsub)) continue;
        if (nd.child >= 0) {
            for (int q = 7; q >= 0; --q) stack[top_++] = nd.child + q;
            continue;
        }
        if (nd.local >= 0) add_leaf(static_cast<std::size_t>(nd.local), x, sc);
    }
}

std::vector<std::uint32_t> MpuField::blended_leaves(const Vec3& pw) const {
    const Vec3 dw = pw - origin_;
    EvalScratch sc;
    find_leaves({dw.x * scale_.x, dw.y * scale_.y, dw.z * scale_.z}, sc);
    return sc.leaf;
}

std::uint64_t MpuField::terms_at(const Vec3& pw) const {
    std::uint64_t n = 0;
    for (std::uint32_t l : blended_leaves(pw)) n += locals_[l].count;
    return n;
}

void MpuField::eval_one(const Vec3& pw, double& value, Vec3* grad, PuBlend& blend, EvalScratch& sc) const {
    const bool want_grad = grad != nullptr;
    const Vec3 dw = pw - origin_;
    const Vec3 x{dw.x * scale_.x, dw.y * scale_.y, dw.z * scale_.z};
    blend.reset();
    sc.clear();
    if (std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z)) {
        find_leaves(x, sc);
        blend_leaves(x, want_grad, sc, blend);
    }
    value = blend.finish(grad);
    if (want_grad) *grad = {grad->x * scale_.x, grad->y * scale_.y, grad->z * scale_.z};
}

}  // namespace meshless

namespace meshless {

void MpuField::save_state(FieldStateWriter& w) const {
    if (region_) throw InvalidArgument("mpu: a field built over one region of the points cannot be saved");
    put_frame(w, origin_, scale_, bounds_);
    std::vector<double> nf;
    std::vector<std::int32_t> links;
    nf.reserve(5 * nodes_.size());
    links.reserve(2 * nodes_.size());
    for (const Node& n : nodes_) {
        nf.insert(nf.end(), {n.c.x, n.c.y, n.c.z, n.half, n.r});
        links.insert(links.end(), {n.child, n.local});
    }
    w.put("nodes", std::span<const double>(nf));
    w.put("node_links", std::span<const std::int32_t>(links));
    put_locals(w, locals_);
    put_centres(w, px_, py_, pz_);  // a point is a centre of every leaf whose sphere holds it: ~10x repeated
    w.put("lambda", std::span<const double>(lambda_));
    // The file keeps the lists of version 1's grid (about one cell per leaf); load_state checks
    // them and builds the finer grid that evaluation uses.
    std::vector<std::uint32_t> first, list;
    lookup_lists(std::int64_t{1} << lookup_level(1), first, list);
    w.put("lookup_first", std::span<const std::uint32_t>(first));
    w.put("lookup_leaves", std::span<const std::uint32_t>(list));
}

namespace {
/// The largest magnitude of a node's centre, half edge or radius in a loaded state (fitting frame).
constexpr double kMaxNodeValue = 1e150;
}  // namespace

std::unique_ptr<MpuField> MpuField::load_state(FieldState& s) {
    std::unique_ptr<MpuField> f(new MpuField);
    take_frame(s, f->origin_, f->scale_, f->bounds_);
    f->locals_ = take_locals(s);
    const std::size_t nl = f->locals_.size();
    if (nl == 0) s.fail("locals", "no local interpolant");
    {
        const std::vector<double> nf = s.take_f64("nodes");
        if (nf.empty() || nf.size() % 5 != 0) s.fail("nodes", "array 'nodes' does not hold 5 values per node");
        const std::size_t nn = nf.size() / 5;
        if (nn > 0x7FFFFFF0u) s.fail("nodes", "more than 2^31 nodes");
        const std::vector<std::int32_t> links = s.take_i32("node_links", 2 * nn);
        f->nodes_.resize(nn);
        std::vector<std::uint8_t> depth(nn, 0), referenced(nn, 0), local_seen(nl, 0);
        std::size_t leaves = 0;
        for (std::size_t i = 0; i < nn; ++i) {
            const double* v = nf.data() + 5 * i;
            for (int k = 0; k < 5; ++k) {
                if (!std::isfinite(v[k])) s.fail("nodes", "node " + std::to_string(i) + ": non-finite value");
                // the octree lives in the unit-sized fitting frame; bounded so that no sum or square
                // of node values (lookup ranges, sphere tests) overflows to inf, and no inf - inf
                // or inf * 0 makes a NaN (a product that overflows is +-inf, which the clamps take)
                if (std::fabs(v[k]) > kMaxNodeValue) {
                    char buf[32];
                    std::snprintf(buf, sizeof buf, "%g", v[k]);
                    s.fail("nodes", "node " + std::to_string(i) + ": value " + buf + " beyond +-1e150");
                }
            }
            if (!(v[3] > 0) || !(v[4] >= 0)) s.fail("nodes", "node " + std::to_string(i) + ": half edge not > 0 or radius < 0");
            Node& n = f->nodes_[i];
            n.c = {v[0], v[1], v[2]};
            n.half = v[3];
            n.r = n.rsub = v[4];
            n.child = links[2 * i];
            n.local = links[2 * i + 1];
            const std::string who = "node " + std::to_string(i);
            if (i > 0 && !referenced[i]) s.fail("node_links", who + " is nobody's child");
            if (n.child >= 0) {
                if (static_cast<std::size_t>(n.child) <= i || static_cast<std::size_t>(n.child) + 8 > nn)
                    s.fail("node_links", who + ": children at " + std::to_string(n.child) + " outside " +
                                             std::to_string(i + 1) + ".." + std::to_string(nn - 1) + " (8 needed)");
                if (n.local != -1) s.fail("node_links", who + " has children and a local");
                if (depth[i] >= 60) s.fail("node_links", who + ": octree deeper than 60 levels");
                for (int q = 0; q < 8; ++q) {
                    const std::size_t ch = static_cast<std::size_t>(n.child) + q;
                    if (referenced[ch]) s.fail("node_links", "node " + std::to_string(ch) + " has two parents");
                    referenced[ch] = 1;
                    depth[ch] = static_cast<std::uint8_t>(depth[i] + 1);
                }
            } else {
                if (n.child != -1) s.fail("node_links", who + ": child index " + std::to_string(n.child));
                if (n.local < 0 || static_cast<std::size_t>(n.local) >= nl)
                    s.fail("node_links", who + ": local " + std::to_string(n.local) + " of " + std::to_string(nl));
                if (local_seen[static_cast<std::size_t>(n.local)]) s.fail("node_links", who + ": local " + std::to_string(n.local) + " used twice");
                local_seen[static_cast<std::size_t>(n.local)] = 1;
                ++leaves;
            }
        }
        if (leaves != nl) s.fail("node_links", std::to_string(leaves) + " leaves for " + std::to_string(nl) + " locals");
    }
    take_centres(s, f->px_, f->py_, f->pz_);
    const std::size_t np = f->px_.size();
    if (np > 0xFFFFFFF0u) s.fail("centre_index", "more than 2^32-16 centres");
    f->lambda_ = s.take_f64("lambda", np);
    if (f->lambda_.size() != np) s.fail("lambda", "not one lambda per centre entry");
    check_local_ranges(s, f->locals_, np);
    f->compute_subtree_radii();
    f->lookup_geometry(f->lookup_level(1));  // the file's grid (save_state)
    const std::size_t ncell = static_cast<std::size_t>(f->g_ * f->g_ * f->g_);
    const std::vector<std::uint32_t> first = s.take_u32("lookup_first", ncell + 1);
    const std::vector<std::uint32_t> list = s.take_u32("lookup_leaves");
    if (first[0] != 0 || first[ncell] != list.size()) s.fail("lookup_first", "lookup lists do not span the leaf entries");
    for (std::size_t c = 0; c < ncell; ++c)
        if (first[c] > first[c + 1]) s.fail("lookup_first", "lookup lists not ascending at cell " + std::to_string(c));
    for (std::size_t k = 0; k < list.size(); ++k)
        if (list[k] >= nl) s.fail("lookup_leaves", "entry " + std::to_string(k) + " names leaf " + std::to_string(list[k]) + " of " + std::to_string(nl));
    f->build_lookup();
    return f;
}

}  // namespace meshless
