#include "kernels/point_set.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meshless {

std::array<Vec3, 2> bounding_box(std::span<const Vec3> pos) {
    if (pos.empty()) return {Vec3{}, Vec3{}};
    Vec3 lo = pos[0], hi = pos[0];
    for (const Vec3& p : pos) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    return {lo, hi};
}

std::array<Vec3, 2> PointSet::bounds() const { return bounding_box(pos); }

std::array<double, 2> PointSet::value_range() const {
    if (value.empty()) return {std::nan(""), std::nan("")};
    const auto [lo, hi] = std::minmax_element(value.begin(), value.end());
    return {*lo, *hi};
}

}  // namespace meshless
