#include "kernels/binning_rule_scan.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace meshless {

namespace {

using Cell = std::array<std::uint64_t, 3>;  // (the rule descends at most ~33 levels for n < 2^32)

// The cell of unit position u at level l along the split axes (0 along the others).
Cell cell_at(const Vec3& u, int l, const std::array<bool, 3>& split) {
    const double side = std::ldexp(1.0, l);
    Cell c{0, 0, 0};
    for (int a = 0; a < 3; ++a)
        if (split[static_cast<std::size_t>(a)])
            c[static_cast<std::size_t>(a)] = static_cast<std::uint64_t>(std::min(std::floor(u[a] * side), side - 1));
    return c;
}

}  // namespace

int binning_rule_level_scanned(const PointScan& scan, std::uint64_t n, const std::array<Vec3, 2>& bounds,
                               const BinningGridParams& params, int* scans) {
    check_binning_input(n, bounds, params);
    const std::array<bool, 3> split = binning_split_axes(bounds, params);
    const int max_depth = std::max(0, params.max_depth);
    std::vector<std::uint64_t> hist(static_cast<std::size_t>(max_depth) + 2, 0);  // collected levels, counted
    int made = 0;
    // (as binning_rule_levels: a set of one point, the depth cap or no split axis stop at the root)
    std::vector<Cell> frontier;  // the nodes of the current level the rule descends, sorted
    if (n <= 1 || max_depth == 0 || !(split[0] || split[1] || split[2])) ++hist[0];
    else frontier.push_back(Cell{0, 0, 0});
    for (int l = 0; !frontier.empty(); ++l) {
        // one scan: each descended node's children, counted up to 2 (empty, one point, more)
        std::vector<std::array<std::uint8_t, 8>> count(frontier.size(), std::array<std::uint8_t, 8>{});
        std::size_t last = 0;  // the node of the previous point (points come in runs)
        scan([&](std::span<const Vec3> chunk) {
            for (const Vec3& p : chunk) {
                const Cell c = cell_at(binning_unit_position(p, bounds, split), l + 1, split);
                const Cell node{c[0] >> 1, c[1] >> 1, c[2] >> 1};
                std::size_t i = last;
                if (frontier[i] != node) {
                    const auto it = std::lower_bound(frontier.begin(), frontier.end(), node);
                    if (it == frontier.end() || *it != node) continue;
                    i = static_cast<std::size_t>(it - frontier.begin());
                    last = i;
                }
                const int child = int(c[0] & 1u) | int(c[1] & 1u) << 1 | int(c[2] & 1u) << 2;
                std::uint8_t& k = count[i][static_cast<std::size_t>(child)];
                k = static_cast<std::uint8_t>(std::min(2, k + 1));
            }
        });
        ++made;
        std::vector<Cell> next;
        for (std::size_t i = 0; i < frontier.size(); ++i) {
            bool empty = false;
            for (int q = 0; q < 8; ++q) {
                const bool exists = !((q & 1) && !split[0]) && !((q & 2) && !split[1]) && !((q & 4) && !split[2]);
                if (exists && count[i][static_cast<std::size_t>(q)] == 0) empty = true;
            }
            if (empty) {  // a node with an empty child collects its level
                ++hist[static_cast<std::size_t>(l)];
                continue;
            }
            for (int q = 0; q < 8; ++q) {
                if (count[i][static_cast<std::size_t>(q)] == 0) continue;  // (a child along an unsplit axis)
                if (count[i][static_cast<std::size_t>(q)] == 1 || l + 1 >= max_depth) {
                    ++hist[static_cast<std::size_t>(l) + 1];  // a leaf, or at the depth cap
                    continue;
                }
                const Cell& f = frontier[i];
                next.push_back(Cell{2 * f[0] + (q & 1 ? 1u : 0u), 2 * f[1] + (q & 2 ? 1u : 0u), 2 * f[2] + (q & 4 ? 1u : 0u)});
            }
        }
        std::sort(next.begin(), next.end());
        frontier.swap(next);
    }
    if (scans) *scans = made;
    // the lower median of the collected levels
    std::uint64_t total = 0;
    for (std::uint64_t h : hist) total += h;
    const std::uint64_t m = (total - 1) / 2;
    std::uint64_t seen = 0;
    for (std::size_t lv = 0; lv < hist.size(); ++lv) {
        seen += hist[lv];
        if (seen > m) return static_cast<int>(lv);
    }
    return 0;
}

BinningGrid make_binning_grid_scanned(const PointScan& scan, std::uint64_t n, const std::array<Vec3, 2>& bounds,
                                      const BinningGridParams& params) {
    return binning_grid_of(bounds, binning_rule_level_scanned(scan, n, bounds, params), params);
}

}  // namespace meshless
