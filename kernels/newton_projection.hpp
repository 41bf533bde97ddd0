// Approximate projection onto an isosurface: one Newton-Raphson step along the gradient
// (dissertation section 3.3.2, Eq. 3.5) with the displacement criterion of Fig. 3.3.
//
//   t  = (f_I - f(p)) / (grad f(p) . grad f(p))
//   p' = p + t * grad f(p)
// The step is rejected when |p' - p| > delta_d, with delta_d = 1/2 * sqrt(sx^2 + sy^2 + sz^2) for a
// cell of edge lengths (sx, sy, sz), or when the gradient vanishes. Units: positions and cell sizes
// in world units, gradient in value units per world unit. Pure, reentrant.
#pragma once
#include "kernels/vec3.hpp"

namespace meshless {

enum class NewtonStatus { ok, too_far, flat };

struct NewtonResult {
    Vec3 pos;
    NewtonStatus status = NewtonStatus::ok;
};

/// Half the cell diagonal: the displacement threshold delta_d of section 3.3.2.
inline double displacement_threshold(const Vec3& cell_size) { return 0.5 * norm(cell_size); }

inline NewtonResult newton_step(const Vec3& p, double value, const Vec3& grad, double iso,
                                double max_displacement) {
    const double gg = dot(grad, grad);
    if (!(gg > 0.0)) return {p, NewtonStatus::flat};
    const double t = (iso - value) / gg;
    const Vec3 step = grad * t;
    if (dot(step, step) > max_displacement * max_displacement) return {p + step, NewtonStatus::too_far};
    return {p + step, NewtonStatus::ok};
}

}  // namespace meshless
