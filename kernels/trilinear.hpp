// Trilinear interpolation inside one cell: value and analytic gradient (dissertation Eq. 3.1).
//
// Corner values c[8] are indexed dx + 2*dy + 4*dz (dx,dy,dz in {0,1}). (u,v,w) are local cell
// coordinates, [0,1] inside the cell; values outside extrapolate the same polynomial. The gradient
// returned is with respect to local coordinates; divide component-wise by the cell edge lengths to
// get value units per world unit (see to_world_gradient). Pure, reentrant, no allocation.
#pragma once
#include "kernels/vec3.hpp"

namespace meshless {

struct ValueGrad {
    double value = 0;
    Vec3 grad;  ///< d value / d (u,v,w)
};

/// Value and local gradient of the trilinear interpolant of c at (u,v,w).
inline ValueGrad trilinear(const double c[8], double u, double v, double w) {
    // interpolate along x on the four x-edges
    const double c00 = c[0] + u * (c[1] - c[0]);
    const double c10 = c[2] + u * (c[3] - c[2]);
    const double c01 = c[4] + u * (c[5] - c[4]);
    const double c11 = c[6] + u * (c[7] - c[6]);
    const double c0 = c00 + v * (c10 - c00);
    const double c1 = c01 + v * (c11 - c01);
    ValueGrad r;
    r.value = c0 + w * (c1 - c0);
    // d/du
    const double d00 = c[1] - c[0], d10 = c[3] - c[2], d01 = c[5] - c[4], d11 = c[7] - c[6];
    const double d0 = d00 + v * (d10 - d00), d1 = d01 + v * (d11 - d01);
    r.grad.x = d0 + w * (d1 - d0);
    r.grad.y = (c10 - c00) + w * ((c11 - c01) - (c10 - c00));
    r.grad.z = c1 - c0;
    return r;
}

/// Local-coordinate gradient -> world gradient for a cell of edge lengths s.
inline Vec3 to_world_gradient(const Vec3& g_local, const Vec3& s) {
    return {g_local.x / s.x, g_local.y / s.y, g_local.z / s.z};
}

}  // namespace meshless
