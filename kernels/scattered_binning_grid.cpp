#include "kernels/scattered_binning_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

struct RuleWalk {
    std::span<const Vec3> unit;
    std::array<bool, 3> split;
    int max_depth;
    std::vector<std::uint32_t> idx, tmp;
    std::vector<int> levels;

    // node: idx[b, e), lower corner lo, edge `size` (same on every axis of the unit cube)
    void visit(std::size_t b, std::size_t e, const Vec3& lo, double size, int level) {
        if (e - b <= 1 || level >= max_depth) {
            levels.push_back(level);
            return;
        }
        const double half = 0.5 * size;
        const Vec3 mid = lo + Vec3{half, half, half};
        auto child = [&](const Vec3& u) {
            int c = 0;
            if (split[0] && u.x >= mid.x) c |= 1;
            if (split[1] && u.y >= mid.y) c |= 2;
            if (split[2] && u.z >= mid.z) c |= 4;
            return c;
        };
        std::array<std::size_t, 9> count{};
        for (std::size_t i = b; i < e; ++i) ++count[static_cast<std::size_t>(child(unit[idx[i]])) + 1];
        // a child exists for every combination of the split axes' bits
        bool empty = false;
        for (int c = 0; c < 8; ++c) {
            const bool exists = !((c & 1) && !split[0]) && !((c & 2) && !split[1]) && !((c & 4) && !split[2]);
            if (exists && count[static_cast<std::size_t>(c) + 1] == 0) empty = true;
        }
        if (empty) {
            levels.push_back(level);
            return;
        }
        for (int c = 0; c < 8; ++c) count[static_cast<std::size_t>(c) + 1] += count[static_cast<std::size_t>(c)];
        std::array<std::size_t, 9> at = count;
        for (std::size_t i = b; i < e; ++i) tmp[b + at[static_cast<std::size_t>(child(unit[idx[i]]))]++] = idx[i];
        std::copy(tmp.begin() + static_cast<std::ptrdiff_t>(b), tmp.begin() + static_cast<std::ptrdiff_t>(e),
                  idx.begin() + static_cast<std::ptrdiff_t>(b));
        for (int c = 0; c < 8; ++c) {
            const std::size_t cb = b + count[static_cast<std::size_t>(c)], ce = b + count[static_cast<std::size_t>(c) + 1];
            if (ce == cb) continue;  // a child of an unsplit axis
            const Vec3 clo{lo.x + ((c & 1) ? half : 0.0), lo.y + ((c & 2) ? half : 0.0), lo.z + ((c & 4) ? half : 0.0)};
            visit(cb, ce, clo, half, level + 1);
        }
    }
};

}  // namespace

std::array<std::int64_t, 3> BinningGrid::cell_of(const Vec3& p) const {
    const Vec3 c = to_cell_coords(p);
    std::array<std::int64_t, 3> r{};
    for (int a = 0; a < 3; ++a) {
        const double f = std::floor(c[a]);
        const double hi = double(dims[static_cast<std::size_t>(a)] - 2);
        r[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(std::clamp(std::isfinite(f) ? f : 1.0, 1.0, std::max(1.0, hi)));
    }
    return r;
}

std::vector<int> binning_rule_levels(std::span<const Vec3> unit, std::array<bool, 3> split, int max_depth) {
    RuleWalk w{unit, split, std::max(0, max_depth), {}, {}, {}};
    if (unit.empty()) return {};
    w.idx.resize(unit.size());
    w.tmp.resize(unit.size());
    for (std::size_t i = 0; i < unit.size(); ++i) w.idx[i] = static_cast<std::uint32_t>(i);
    if (!split[0] && !split[1] && !split[2]) return {0};
    w.visit(0, unit.size(), Vec3{0, 0, 0}, 1.0, 0);
    return std::move(w.levels);
}

int median_level(std::vector<int> levels) {
    if (levels.empty()) return 0;
    const std::size_t m = (levels.size() - 1) / 2;
    std::nth_element(levels.begin(), levels.begin() + static_cast<std::ptrdiff_t>(m), levels.end());
    return levels[m];
}

std::array<bool, 3> binning_split_axes(const std::array<Vec3, 2>& bounds, const BinningGridParams& params) {
    const Vec3 ext = bounds[1] - bounds[0];
    const double emax = std::max({ext.x, ext.y, ext.z});
    std::array<bool, 3> split{};
    for (int a = 0; a < 3; ++a) split[static_cast<std::size_t>(a)] = ext[a] > params.degenerate_axis * emax;
    return split;
}

Vec3 binning_unit_position(const Vec3& p, const std::array<Vec3, 2>& bounds, const std::array<bool, 3>& split) {
    const Vec3 ext = bounds[1] - bounds[0];
    auto scaled = [&](double v, int a) {
        return split[static_cast<std::size_t>(a)] ? std::clamp((v - bounds[0][a]) / ext[a], 0.0, 1.0) : 0.0;
    };
    return {scaled(p.x, 0), scaled(p.y, 1), scaled(p.z, 2)};
}

void check_binning_input(std::uint64_t n, const std::array<Vec3, 2>& bounds, const BinningGridParams& params) {
    if (n == 0) throw InvalidArgument("binning grid: no points");
    if (n >= std::numeric_limits<std::uint32_t>::max()) throw InvalidArgument("binning grid: more than 2^32 - 1 points");
    if (params.max_cells < 27) throw InvalidArgument("binning grid: max_cells below 27 (one 3x3x3 stencil)");
    const Vec3 ext = bounds[1] - bounds[0];
    if (!(std::max({ext.x, ext.y, ext.z}) > 0)) throw InvalidArgument("binning grid: every point coincides");
}

BinningGrid make_binning_grid(std::span<const Vec3> pos, const BinningGridParams& params) {
    if (pos.empty()) throw InvalidArgument("binning grid: no points");
    Vec3 lo = pos[0], hi = pos[0];
    for (const Vec3& p : pos) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const std::array<Vec3, 2> bounds{lo, hi};
    check_binning_input(pos.size(), bounds, params);
    const std::array<bool, 3> split = binning_split_axes(bounds, params);
    // rescale into the unit cube, axis by axis
    std::vector<Vec3> unit(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) unit[i] = binning_unit_position(pos[i], bounds, split);
    const int rule_level = median_level(binning_rule_levels(unit, split, params.max_depth));
    unit = {};
    return binning_grid_of(bounds, rule_level, params);
}

BinningGrid binning_grid_of(const std::array<Vec3, 2>& bounds, int rule_level, const BinningGridParams& params) {
    BinningGrid g;
    g.bounds = bounds;
    const auto [lo, hi] = bounds;
    const Vec3 ext = hi - lo;
    const std::array<bool, 3> split = binning_split_axes(bounds, params);
    for (int a = 0; a < 3; ++a) g.degenerate[static_cast<std::size_t>(a)] = !split[static_cast<std::size_t>(a)];
    g.rule_level = rule_level;

    auto cells_at = [&](int l) {
        double c = 1;
        for (int a = 0; a < 3; ++a) c *= split[static_cast<std::size_t>(a)] ? std::ldexp(1.0, l) + 2 : 3.0;
        return c;
    };
    int l = std::min(g.rule_level, std::max(0, params.max_level));
    while (l > 0 && cells_at(l) > double(params.max_cells)) --l;
    g.level = l;
    g.coarsened = l < g.rule_level;
    const double n = std::ldexp(1.0, l);
    double hmax = 0;
    for (int a = 0; a < 3; ++a)
        if (split[static_cast<std::size_t>(a)]) hmax = std::max(hmax, ext[a] / n);
    double o[3], h[3];
    for (int a = 0; a < 3; ++a) {
        const auto ua = static_cast<std::size_t>(a);
        if (split[ua]) {
            h[a] = ext[a] / n;
            o[a] = lo[a] - h[a];
            g.dims[ua] = (std::int64_t{1} << l) + 2;
        } else {
            h[a] = hmax;
            o[a] = 0.5 * (lo[a] + hi[a]) - 1.5 * h[a];
            g.dims[ua] = 3;
        }
    }
    g.origin = {o[0], o[1], o[2]};
    g.cell = {h[0], h[1], h[2]};
    return g;
}

BinnedPoints bin_points(const BinningGrid& g, std::span<const Vec3> pos) {
    if (pos.size() >= std::numeric_limits<std::uint32_t>::max()) throw InvalidArgument("binning grid: more than 2^32 - 1 points");
    BinnedPoints b;
    const auto cells = static_cast<std::size_t>(g.cell_count());
    b.start.assign(cells + 1, 0);
    std::vector<std::uint32_t> cell(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const auto c = g.cell_of(pos[i]);
        cell[i] = static_cast<std::uint32_t>(g.index(c[0], c[1], c[2]));
        ++b.start[cell[i] + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) {
        if (b.start[c + 1] == 0) {
            ++b.empty_cells;
            const std::int64_t k = static_cast<std::int64_t>(c) / (g.dims[0] * g.dims[1]);
            const std::int64_t j = (static_cast<std::int64_t>(c) / g.dims[0]) % g.dims[1];
            const std::int64_t i = static_cast<std::int64_t>(c) % g.dims[0];
            const bool border = i == 0 || j == 0 || k == 0 || i == g.dims[0] - 1 || j == g.dims[1] - 1 || k == g.dims[2] - 1;
            if (!border) ++b.empty_interior_cells;
        }
        b.max_per_cell = std::max(b.max_per_cell, b.start[c + 1]);
        b.start[c + 1] += b.start[c];
    }
    b.order.resize(pos.size());
    std::vector<std::uint32_t> at(b.start.begin(), b.start.end() - 1);
    for (std::size_t i = 0; i < pos.size(); ++i) b.order[at[cell[i]]++] = static_cast<std::uint32_t>(i);
    return b;
}

}  // namespace meshless
