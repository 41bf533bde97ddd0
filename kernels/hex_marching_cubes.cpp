#include "kernels/hex_marching_cubes.hpp"

#include <algorithm>

namespace meshless {

int hex_marching_cubes(const HexCell& cell, double iso, bool left_handed, std::array<HexTriangle, kMcMaxTriangles>& out) {
    int code = 0;
    for (int c = 0; c < 8; ++c)
        if (cell.value[static_cast<std::size_t>(c)] >= iso) code |= 1 << c;
    const McCase& mc = marching_cubes_table().cases[static_cast<std::size_t>(code)];
    if (mc.triangle_count == 0) return 0;
    std::array<Vec3, 12> at{};
    for (unsigned m = mc.edge_mask; m; m &= m - 1) {
        const int e = __builtin_ctz(m);
        const auto [a, b] = kMcEdgeCorners[static_cast<std::size_t>(e)];
        const double va = cell.value[static_cast<std::size_t>(a)], vb = cell.value[static_cast<std::size_t>(b)];
        const double t = (iso - va) / (vb - va);
        const Vec3& pa = cell.corner[static_cast<std::size_t>(a)];
        at[static_cast<std::size_t>(e)] = pa + (cell.corner[static_cast<std::size_t>(b)] - pa) * t;
    }
    for (int t = 0; t < mc.triangle_count; ++t) {
        HexTriangle& tri = out[static_cast<std::size_t>(t)];
        const auto* e = &mc.edges[static_cast<std::size_t>(3 * t)];
        tri.v[0] = at[e[0]];
        tri.v[1] = at[e[left_handed ? 2 : 1]];
        tri.v[2] = at[e[left_handed ? 1 : 2]];
    }
    return mc.triangle_count;
}

std::array<double, 2> hex_jacobian_range(const std::array<Vec3, 8>& corner) {
    double lo = 0, hi = 0;
    for (int c = 0; c < 8; ++c) {
        // The three edges leaving corner c, each towards the neighbour along +axis (or -axis, negated).
        Vec3 e[3];
        for (int axis = 0; axis < 3; ++axis) {
            const int bit = 1 << axis;
            const int n = c ^ bit;
            const Vec3 d = corner[static_cast<std::size_t>(n)] - corner[static_cast<std::size_t>(c)];
            e[axis] = (c & bit) ? -d : d;
        }
        const double det = dot(e[0], cross(e[1], e[2]));
        if (c == 0) lo = hi = det;
        lo = std::min(lo, det);
        hi = std::max(hi, det);
    }
    return {lo, hi};
}

}  // namespace meshless
