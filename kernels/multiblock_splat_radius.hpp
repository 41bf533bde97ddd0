// The splat radius of a multiblock isosurface point (dissertation section 4.4):
//
//   r = 2 (1 + d / l) sqrt(2 A / (pi n (n + 1)))
//
// A: area of the marching-cubes triangle the point was seeded in, n: the barycentric lattice
// parameter (n(n+1)/2 samples per triangle, kernels/barycentric_lattice.hpp), l: length of the
// diagonal of the cell the triangle lies in, d: the distance the Newton projection moved the point.
// sqrt(2A / (pi n(n+1))) is the radius of a disc of area A / (n(n+1)/2): with no displacement the
// samples' discs tile the triangle without holes (the factor 2 gives overlap); a point that moved
// is enlarged linearly with its displacement, since the sampling around it thins out.
// Split in two so the seed records carry the base radius (SeedRecord::base_radius) and the
// projection applies the displacement factor.
// Units: world units (A in world units^2). Pure, header-only, throws nothing. l <= 0 or not
// finite (a degenerate cell never seeds; defensive) counts as no enlargement: r = 2 * base.
#pragma once
#include <cmath>
#include <numbers>

namespace meshless {

/// sqrt(2A / (pi n (n+1))); 0 when A <= 0.
inline double lattice_base_radius(double area, int n) {
    if (!(area > 0) || n < 1) return 0.0;
    return std::sqrt(2.0 * area / (std::numbers::pi * n * (n + 1.0)));
}

/// 2 (1 + d/l) base.
inline double multiblock_splat_radius(double base, double d, double l) {
    const double grow = (l > 0 && std::isfinite(l) && std::isfinite(d)) ? d / l : 0.0;
    return 2.0 * (1.0 + grow) * base;
}

/// The whole formula, r(A, n, d, l).
inline double multiblock_splat_radius(double area, int n, double d, double l) {
    return multiblock_splat_radius(lattice_base_radius(area, n), d, l);
}

}  // namespace meshless
