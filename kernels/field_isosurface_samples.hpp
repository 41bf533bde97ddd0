// A dense sampling of a meshless field's own isosurface F = iso (kernels/field.hpp), the reference
// of the scattered benchmark's completeness measure: "coverage (>= 99% of a dense sampling of the field's own
// isosurface within one splat radius)". Where kernels/surface_coverage.hpp samples the *true*
// isosurface of an analytic function (how well the field and the extraction together match the
// truth), this samples the surface the field itself defines, so covering it measures the extraction
// alone (dissertation section 5.6: does marching the stencils find every part of F = iso?).
// The rule of sample_isosurface, with the field in place of the function: points of a jittered grid
// of spacing `spacing` over the box (one per grid cube, SplitMix seeded by seed + the slab index, so
// the set does not depend on the thread count) whose first-order distance |F - iso| / |grad F| is
// below `spacing` are projected by Newton steps along the gradient (at most 30, until the step is
// below 1e-10 of the box diagonal); a point is kept when it converged, moved less than spacing *
// sqrt(3), stayed finite (NaN: outside the field's support) and lies in the box shrunk by `margin`.
// Evaluation in batches of one grid slab, slabs in parallel (oneTBB; Field::evaluate is thread-safe).
// Output: in slab order. Units: world. Throws InvalidArgument as sample_isosurface does (spacing <= 0,
// an empty or inverted box, over 1e5 cells per axis).
#pragma once
#include <vector>

#include "kernels/field.hpp"
#include "kernels/surface_coverage.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

std::vector<Vec3> sample_field_isosurface(const Field& f, double iso, const Box3& box, const SurfaceSampling& s = {});

}  // namespace meshless
