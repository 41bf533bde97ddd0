// The local Delaunay tetrahedrization of one 3x3x3 stencil's points (dissertation section 5.4: "We
// use Delaunay methods to tetrahedrize the stencil point set"), by CGAL's Delaunay_triangulation_3
// with exact predicates (Exact_predicates_inexact_constructions_kernel). CGAL is included in
// stencil_delaunay.cpp only (and triangle_pair_intersections.cpp), compiled as its own object
// library (kernels/CMakeLists.txt).
//
// Input: positions (any frame; callers pass stencil-local cell coordinates, which keeps 1e6 world
// offsets out of the arithmetic). Output: the finite tetrahedra as index quadruples into `pts`, in
// a deterministic order (the triangulation's cell order for this input; CGAL's spatial sort with a
// fixed seed), each positively oriented. Duplicate positions keep one vertex (the first in the
// input). Returns the status: ok; too_few (fewer than 4 distinct points) or flat (all points
// coplanar: the triangulation has dimension < 3), both with no tetrahedra; failed when a coordinate
// is not finite or CGAL threw (the reason in *what when given). Never throws but std::bad_alloc.
// Pure and reentrant (no shared state); allocates its result.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

enum class DelaunayStatus { ok, too_few, flat, failed };

DelaunayStatus stencil_delaunay(std::span<const Vec3> pts, std::vector<std::array<std::uint32_t, 4>>& tets, std::string* what = nullptr);

}  // namespace meshless
