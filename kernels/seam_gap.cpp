#include "kernels/seam_gap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x & 0x1fffff) << 42) | (static_cast<std::uint64_t>(y & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(z & 0x1fffff);
}

}  // namespace

SeamGaps seam_gaps(std::span<const Vec3> pos, std::span<const Vec3> normal, std::span<const float> radius,
                   std::span<const std::uint32_t> block, double curvature_radius, bool across) {
    if (normal.size() != pos.size() || radius.size() != pos.size() || block.size() != pos.size())
        throw InvalidArgument("seam_gaps: points, normals, radii and blocks differ in length");
    SeamGaps out;
    std::vector<std::size_t> ok;
    double cell = 0;
    for (std::size_t i = 0; i < pos.size(); ++i) {
        if (!finite(pos[i]) || !finite(normal[i]) || !(radius[i] > 0) || !std::isfinite(radius[i])) continue;
        ok.push_back(i);
        cell = std::max(cell, static_cast<double>(radius[i]));
    }
    if (ok.empty()) return out;
    auto cell_of = [&](const Vec3& p) {
        return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(p.x / cell)),
                                           static_cast<std::int64_t>(std::floor(p.y / cell)),
                                           static_cast<std::int64_t>(std::floor(p.z / cell))};
    };
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid;
    for (std::size_t i : ok) {
        const auto c = cell_of(pos[i]);
        grid[key(c[0], c[1], c[2])].push_back(i);
    }
    std::vector<double> gaps;
    for (std::size_t i : ok) {
        const auto c = cell_of(pos[i]);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const auto it = grid.find(key(c[0] + dx, c[1] + dy, c[2] + dz));
                    if (it == grid.end()) continue;
                    for (std::size_t j : it->second) {
                        if ((block[j] == block[i]) == across || j == i) continue;
                        const Vec3 d = pos[i] - pos[j];
                        const double r = std::max(radius[i], radius[j]);
                        const double dd = dot(d, d);
                        if (dd > r * r) continue;
                        const double n = norm(normal[j]);
                        if (!(n > 0)) continue;
                        gaps.push_back(std::abs(dot(normal[j], d)) / n);
                        if (curvature_radius > 0 && std::isfinite(curvature_radius))
                            out.max_curvature_term = std::max(out.max_curvature_term, dd / (2 * curvature_radius));
                    }
                }
    }
    out.pairs = gaps.size();
    if (gaps.empty()) return out;
    out.max_gap = *std::max_element(gaps.begin(), gaps.end());
    const std::size_t k = static_cast<std::size_t>(0.99 * static_cast<double>(gaps.size() - 1));
    std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(k), gaps.end());
    out.p99_gap = gaps[k];
    return out;
}

}  // namespace meshless
