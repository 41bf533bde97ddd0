// Projection of one paradigm-(C) sample onto the isosurface f = iso of its cell's trilinear
// interpolant (dissertation section 3.3): `approx` = one Newton step with the displacement criterion
// (Eq. 3.5, section 3.3.2), `exact` = ray-trilinear intersection by the cubic of Eq. 3.3 (section
// 3.3.1), `none` = the unprojected sample (left image of Fig. 3.4).
//
// Normals follow VTK's convention (vtkFlyingEdges3D, vtkContourFilter with ComputeNormals): the unit
// normal is -grad f / |grad f|, pointing towards decreasing values (out of a dense object).
// `approx` reuses the sample's gradient for the normal, as section 3.4 suggests ("the gradient can
// be reused for shading"), and records value = iso, the value the Newton step aims at (first-order
// exact: f(p) + grad f(p) . step = iso); this keeps the step to one division and one square root
// per sample. `exact` and `none` record the negated unit gradient and the value of the cell's
// trilinear interpolant at the output position (falling back to the sample's gradient where that
// vanishes). The normal is the float rounding of the negated double unit gradient; negation is exact,
// so every path that projects a sample (fused or two-stage) gives the same bytes. Rejected samples return false and are counted.
// Samples of a paradigm (A) store carry no corners (corner[] is NaN): `none` then keeps the
// sample's own position, gradient and value, and `exact` throws FormatError.
// Pure and reentrant.
#pragma once
#include <cmath>
#include <cstdint>

#include "kernels/exact_projection.hpp"
#include "kernels/newton_projection.hpp"
#include "kernels/records.hpp"
#include "kernels/trilinear.hpp"

namespace meshless {

enum class Projection { none, approx, exact };

/// "none" | "approx" | "exact" (the names the CLI's --projection accepts, cli/common.hpp).
const char* to_string(Projection p);

struct ProjectionStats {
    std::int64_t input = 0;         ///< samples seen
    std::int64_t output = 0;        ///< points emitted
    std::int64_t too_far = 0;       ///< approx: Newton step longer than delta_d (Fig. 3.3)
    std::int64_t flat = 0;          ///< approx: zero gradient
    std::int64_t missed = 0;        ///< exact: no ray hit the isosurface inside the cell
    ProjectionStats& operator+=(const ProjectionStats& o) {
        input += o.input; output += o.output; too_far += o.too_far; flat += o.flat; missed += o.missed;
        return *this;
    }
};

/// The exact and none projections (out of line; project_sample dispatches here). Does not count
/// stats.input.
bool project_sample_cell(const SampleRecord& s, double iso, Projection mode, PointRecord& out,
                         ProjectionStats& stats);

/// Projects s onto f = iso. Returns false (and counts why) when the sample is discarded.
/// The approximate projection is inline: it is the innermost loop of the fused generate+project path.
inline bool project_sample(const SampleRecord& s, double iso, Projection mode, PointRecord& out,
                           ProjectionStats& stats) {
    ++stats.input;
    if (mode != Projection::approx) return project_sample_cell(s, iso, mode, out, stats);
    const Vec3 p{s.pos[0], s.pos[1], s.pos[2]};
    const Vec3 size{s.cell_size[0], s.cell_size[1], s.cell_size[2]};
    const Vec3 g{s.grad[0], s.grad[1], s.grad[2]};
    const NewtonResult r = newton_step(p, s.value, g, iso, displacement_threshold(size));
    if (r.status == NewtonStatus::flat) { ++stats.flat; return false; }
    if (r.status == NewtonStatus::too_far) { ++stats.too_far; return false; }
    const Vec3 n = g * (-1.0 / std::sqrt(dot(g, g)));  // dot(g, g) > 0, or the step was flat; -grad: VTK
    out.pos[0] = static_cast<float>(r.pos.x);
    out.pos[1] = static_cast<float>(r.pos.y);
    out.pos[2] = static_cast<float>(r.pos.z);
    out.normal[0] = static_cast<float>(n.x);
    out.normal[1] = static_cast<float>(n.y);
    out.normal[2] = static_cast<float>(n.z);
    out.radius = s.radius;
    out.value = static_cast<float>(iso);
    ++stats.output;
    return true;
}

}  // namespace meshless
