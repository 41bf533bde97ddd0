// Marching tetrahedra (dissertation section 5.6: "marching tetrahedra to obtain an initial triangle
// approximation for the isosurface"): the isosurface of the linear interpolant of four vertex values
// inside one tetrahedron, as 0, 1 or 2 triangles.
//
// A vertex is inside when its value >= iso (the marching-cubes convention of this project: a cell is
// crossed when some corner is >= iso and some < iso). One vertex apart from the other three gives
// one triangle; two and two give a quadrilateral, split into two triangles along its shorter
// diagonal. Crossing points lie on the edges joining an inside and an outside vertex, at the linear
// interpolation parameter t = (iso - v_a) / (v_b - v_a) in [0, 1].
// Orientation (VTK's convention): every triangle is wound so that its right-hand normal
// (b - a) x (c - a) points to decreasing values of the tetrahedron's linear interpolant (from the
// inside vertices towards the outside ones), whatever the tetrahedron's own orientation.
// Returns the number of triangles written to out[0..n) (n <= 2). A tetrahedron with a non-finite
// value gives none (the caller counts it). Units: positions as given; values in the data's units.
// Pure, reentrant, allocation-free; throws nothing.
#pragma once
#include <array>

#include "kernels/vec3.hpp"

namespace meshless {

using MtTriangle = std::array<Vec3, 3>;

int marching_tetrahedron(const std::array<Vec3, 4>& p, const std::array<double, 4>& v, double iso, std::array<MtTriangle, 2>& out);

}  // namespace meshless
