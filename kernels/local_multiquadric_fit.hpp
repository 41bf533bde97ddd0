// One local multiquadric fit of the RBF-grid (dissertation section 4.3) and MPU (section 5.5)
// fields, with Hardy's c sized to the local's points (section 2.1.1):
//
//   1. c = min(c_global, hardy_c_spacing x s), s = the mean nearest-neighbour distance of the
//      local's points (kernels/local_spacing.hpp). The condition number of a multiquadric system
//      grows steeply with c / s, so a c tied only to the bounding box makes every local of dense
//      data ill-conditioned; capped, c / s stays bounded at any density, while sparse data (where
//      the global c is below the cap) keeps the paper's c.
//   2. A local that is still ill-conditioned at that c (kernels/multiquadric.hpp: its exact solve
//      fails the residual or coefficient-growth bounds, as at sharp edges of CT data, where the
//      flat, wide basis needs huge cancelling coefficients) is fitted again with
//      c = hardy_c_rough x s, and that fit is kept when it interpolates. A narrow basis is less
//      accurate on smooth data but conditioned, and it interpolates instead of approximating
//      through a ridge.
//
// Units: positions and c in the caller's frame; values in data units. Writes the same outputs as
// MultiquadricSolver::fit (out.first is left as given). Thread-safety: one solver per thread.
// Throws only std::bad_alloc.
#pragma once
#include <cstdint>
#include <span>

#include "kernels/field_params.hpp"
#include "kernels/multiquadric.hpp"

namespace meshless {

struct LocalFitResult {
    MultiquadricFitResult fit;
    double c = 0;           ///< the c of the kept fit
    bool refitted = false;  ///< the narrow c of step 2 was kept
};

LocalFitResult fit_local_multiquadric(MultiquadricSolver& solver, std::span<const Vec3> pos, std::span<const double> value,
                                      std::span<const std::uint32_t> idx, double c_global, const FieldParams& params,
                                      MultiquadricLocal& out, std::span<double> lambda);

}  // namespace meshless
