#include "kernels/amr_cover.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meshless {

namespace {

double comp(const Vec3& p, int a) { return a == 0 ? p.x : a == 1 ? p.y : p.z; }
bool finite(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// Per-axis spacing of a (uniform, axis-aligned) cell-centred block, see the header.
std::array<double, 3> spacing(const StructuredBlock& b) {
    std::array<double, 3> h{0, 0, 0};
    double smallest = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (b.dims[static_cast<std::size_t>(a)] < 2) continue;
        const std::int64_t step = a == 0 ? 1 : a == 1 ? b.dims[0] : b.dims[0] * b.dims[1];
        h[static_cast<std::size_t>(a)] = std::abs(comp(b.node[static_cast<std::size_t>(step)], a) - comp(b.node[0], a));
        smallest = std::min(smallest, h[static_cast<std::size_t>(a)]);
    }
    for (int a = 0; a < 3; ++a)
        if (b.dims[static_cast<std::size_t>(a)] < 2) h[static_cast<std::size_t>(a)] = std::isfinite(smallest) ? smallest : 0.0;
    return h;
}

bool inside(const std::array<Vec3, 2>& box, const Vec3& p, double tol) {
    return p.x >= box[0].x - tol && p.x <= box[1].x + tol && p.y >= box[0].y - tol && p.y <= box[1].y + tol &&
           p.z >= box[0].z - tol && p.z <= box[1].z + tol;
}

struct Finer {
    std::array<Vec3, 2> box;
    int level;
};

/// Marks the nodes of b lying in the extent of a finer block; returns the count of valid nodes marked.
std::uint64_t mark(StructuredBlock& b, const std::vector<Finer>& finer, double tol) {
    b.covered.assign(static_cast<std::size_t>(b.node_count()), 0);
    std::uint64_t n_marked = 0;
    for (std::int64_t n = 0; n < b.node_count(); ++n) {
        const Vec3& p = b.node[static_cast<std::size_t>(n)];
        for (const Finer& f : finer) {
            if (f.level <= b.level || !inside(f.box, p, tol)) continue;
            b.covered[static_cast<std::size_t>(n)] = 1;
            if (b.is_valid(n)) ++n_marked;
            break;
        }
    }
    if (n_marked == 0 && std::none_of(b.covered.begin(), b.covered.end(), [](std::uint8_t c) { return c != 0; }))
        b.covered.clear();
    return n_marked;
}

/// The finer-level extents of a hierarchy and a tolerance; empty when there is one level only.
std::vector<Finer> levels_above_zero(const Multiblock& mb, double& tol) {
    std::vector<Finer> out;
    int top = 0;
    for (const auto& b : mb.blocks) top = std::max(top, b.level);
    if (top == 0) return out;
    double size = 0;
    for (const auto& b : mb.blocks) {
        if (b.level == 0 && top == 0) continue;
        const auto e = block_extent(b);
        out.push_back({e, b.level});
        size = std::max({size, e[1].x - e[0].x, e[1].y - e[0].y, e[1].z - e[0].z});
    }
    tol = 1e-9 * size;
    return out;
}

/// Pads one axis of a lattice (dims d, arrays i fastest) with a node layer on each side.
void pad_axis(int a, std::array<std::int64_t, 3>& d, std::vector<Vec3>& pos, std::vector<double>& val,
              std::vector<std::uint8_t>& ok, double h) {
    std::array<std::int64_t, 3> nd = d;
    nd[static_cast<std::size_t>(a)] += 2;
    std::vector<Vec3> P(static_cast<std::size_t>(nd[0] * nd[1] * nd[2]));
    std::vector<double> V(P.size());
    std::vector<std::uint8_t> K(P.size());
    const std::int64_t n = d[static_cast<std::size_t>(a)];
    Vec3 e{a == 0 ? 1.0 : 0.0, a == 1 ? 1.0 : 0.0, a == 2 ? 1.0 : 0.0};
    auto src = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return static_cast<std::size_t>(i + d[0] * (j + d[1] * k)); };
    for (std::int64_t k = 0; k < nd[2]; ++k)
        for (std::int64_t j = 0; j < nd[1]; ++j)
            for (std::int64_t i = 0; i < nd[0]; ++i) {
                std::array<std::int64_t, 3> c{i, j, k};
                const std::int64_t t = c[static_cast<std::size_t>(a)];
                const auto out = static_cast<std::size_t>(i + nd[0] * (j + nd[1] * k));
                auto at = [&](std::int64_t q) {
                    std::array<std::int64_t, 3> s = c;
                    s[static_cast<std::size_t>(a)] = q;
                    return src(s[0], s[1], s[2]);
                };
                if (t >= 1 && t <= n) {
                    const auto s = at(t - 1);
                    P[out] = pos[s], V[out] = val[s], K[out] = ok[s];
                    continue;
                }
                const bool lo = t == 0;
                const auto s0 = at(lo ? 0 : n - 1);
                if (n >= 2) {
                    const auto s1 = at(lo ? 1 : n - 2);
                    P[out] = pos[s0] * 1.5 - pos[s1] * 0.5;
                    V[out] = 1.5 * val[s0] - 0.5 * val[s1];
                    K[out] = ok[s0] && ok[s1];
                } else {
                    P[out] = pos[s0] + e * (lo ? -0.5 * h : 0.5 * h);
                    V[out] = val[s0];
                    K[out] = ok[s0];
                }
            }
    d = nd;
    pos = std::move(P);
    val = std::move(V);
    ok = std::move(K);
}

StructuredBlock padded(const StructuredBlock& b) {
    StructuredBlock p;
    p.name = b.name;
    p.level = b.level;
    p.cell_centred = true;
    if (b.node_count() == 0) return b;
    const auto h = spacing(b);
    std::array<std::int64_t, 3> d = b.dims;
    std::vector<Vec3> pos = b.node;
    std::vector<double> val = b.value;
    std::vector<std::uint8_t> ok(pos.size(), 1);
    for (std::int64_t n = 0; n < b.node_count(); ++n)
        ok[static_cast<std::size_t>(n)] = b.is_valid(n) && finite(pos[static_cast<std::size_t>(n)]) &&
                                          std::isfinite(val[static_cast<std::size_t>(n)]);
    for (int a = 0; a < 3; ++a) pad_axis(a, d, pos, val, ok, h[static_cast<std::size_t>(a)]);
    p.dims = d;
    p.node = std::move(pos);
    p.value = std::move(val);
    if (std::any_of(ok.begin(), ok.end(), [](std::uint8_t v) { return v == 0; })) p.valid = std::move(ok);
    return p;
}

}  // namespace

std::array<Vec3, 2> block_extent(const StructuredBlock& b) {
    const double inf = std::numeric_limits<double>::infinity();
    std::array<Vec3, 2> box{Vec3{inf, inf, inf}, Vec3{-inf, -inf, -inf}};
    for (const Vec3& p : b.node) {
        if (!finite(p)) continue;
        box[0] = {std::min(box[0].x, p.x), std::min(box[0].y, p.y), std::min(box[0].z, p.z)};
        box[1] = {std::max(box[1].x, p.x), std::max(box[1].y, p.y), std::max(box[1].z, p.z)};
    }
    if (b.cell_centred && box[0].x <= box[1].x) {
        const auto h = spacing(b);
        const Vec3 half{0.5 * h[0], 0.5 * h[1], 0.5 * h[2]};
        box[0] = box[0] - half;
        box[1] = box[1] + half;
    }
    return box;
}

std::uint64_t mark_amr_covered(Multiblock& mb) {
    double tol = 0;
    const auto finer = levels_above_zero(mb, tol);
    if (finer.empty()) return 0;
    std::uint64_t total = 0;
    for (auto& b : mb.blocks) total += mark(b, finer, tol);
    mb.covered += total;
    return total;
}

bool has_cell_centred_blocks(const Multiblock& mb) {
    return std::any_of(mb.blocks.begin(), mb.blocks.end(), [](const StructuredBlock& b) { return b.cell_centred; });
}

Multiblock amr_seed_blocks(const Multiblock& mb) {
    Multiblock out;
    out.value_name = mb.value_name;
    out.format = mb.format;
    out.blanked = mb.blanked;
    out.nonfinite = mb.nonfinite;
    out.blocks.reserve(mb.blocks.size());
    for (const auto& b : mb.blocks) out.blocks.push_back(b.cell_centred ? padded(b) : b);
    double tol = 0;
    const auto finer = levels_above_zero(mb, tol);
    if (!finer.empty())
        for (auto& b : out.blocks) (void)mark(b, finer, tol);
    return out;
}

}  // namespace meshless
