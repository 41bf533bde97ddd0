// One local multiquadric fit of the RBF-grid (dissertation section 4.3) and MPU (section 5.5)
// fields, with Hardy's c sized to the local's points (section 2.1.1):
//
//   1. c = min(c_global, hardy_c_spacing x s), s = the mean nearest-neighbour distance of the
//      local's points (kernels/local_spacing.hpp). The condition number of a multiquadric system
//      grows steeply with c / s, so a c tied only to the bounding box makes every local of dense
//      data ill-conditioned; capped, c / s stays bounded at any density, while sparse data (where
//      the global c is below the cap) keeps the paper's c.
//   2. The local is fitted again with c = hardy_c_rough x s (when that is smaller), and keeps the
//      fit with the smaller RMS leave-one-out error (Rippa's formula, kernels/multiquadric.hpp:
//      the error of predicting each point from the others, for about the cost of the factorisation).
//      A wide, flat basis is the more accurate on smooth data; at sharp edges (CT) it overshoots,
//      and often is ill-conditioned, so it needs huge cancelling
//      coefficients or a ridge; the narrow basis is conditioned and interpolates there. Measured on
//      1 M CT samples: RMS error against the volume 10.75 -> 7.21, max 385 -> 147, fit 8.7 -> 13.0 s;
//      Franke and Marschner-Lobb at 10^3..10^6 points unchanged.
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
    bool refitted = false;  ///< the narrow c of step 2 was kept (smaller leave-one-out error)
};

LocalFitResult fit_local_multiquadric(MultiquadricSolver& solver, std::span<const Vec3> pos, std::span<const double> value,
                                      std::span<const std::uint32_t> idx, double c_global, const FieldParams& params,
                                      MultiquadricLocal& out, std::span<double> lambda);

}  // namespace meshless
