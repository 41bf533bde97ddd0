// Exact projection of a sample onto the trilinear isosurface of its cell (dissertation section 3.3.1,
// Eqs. 3.2-3.3, Fig. 3.2a): intersect a ray p + t*dir with f(x) = iso by solving the cubic of Eq. 3.3.
//
// Cell and units: corner values c[8] indexed dx + 2*dy + 4*dz (as kernels/trilinear.hpp); positions are
// LOCAL cell coordinates, the cell is [0,1]^3; convert to world with origin + local * cell_size. `iso`
// is in value units.
// Ray choice (section 3.3.1): first along the gradient of f at p (both directions; the root with the
// smallest |t| whose point lies in the closed cell grown by inside_tol wins); if that misses, rays
// from p towards the corners on the other side of iso from f(p) (the marching-cubes case: a corner is
// "above" when its value >= iso); the intersection inside the cell nearest to p wins. When p is in the
// cell and the cell is active there is always a sign change on such a segment, so `missed` means a
// degenerate cell (e.g. f(p) == iso handled as ok, flat cell, non-active cell).
// The returned point is clamped to [0,1]^3 (moves it by at most inside_tol).
// Preconditions: p_local inside [0,1]^3 (other points work but rays towards corners may then leave
// the cell), finite values. Throws nothing. Pure, reentrant, no allocation.
#pragma once
#include <array>

#include "kernels/vec3.hpp"

namespace meshless {

/// Coefficients {A,B,C,D} (highest power first) of f(p + t*dir) - iso = A t^3 + B t^2 + C t + D for
/// the trilinear interpolant of c (Eq. 3.3). p and dir in local cell coordinates.
std::array<double, 4> trilinear_ray_cubic(const double c[8], const Vec3& p, const Vec3& dir, double iso);

struct ExactParams {
    double inside_tol = 1e-6;  ///< local units a root may lie outside [0,1]^3 and still count as inside
};

enum class ExactStatus { ok, missed };

struct ExactResult {
    Vec3 local;                      ///< projected point (local coords); p_local when missed
    ExactStatus status = ExactStatus::missed;
    int ray = 0;                     ///< 0 = gradient ray, 1..8 = ray towards corner (ray - 1)
};

/// Projects local point p_local onto the trilinear isosurface f = iso inside the cell (see above).
/// Non-convergence is a counted result (status missed), never an exception.
ExactResult exact_project_cell(const double c[8], const Vec3& p_local, double iso,
                               const ExactParams& params = {});

}  // namespace meshless
