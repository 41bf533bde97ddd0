// Intersecting triangle pairs between the pieces of a triangle soup (the naive multiblock marching
// cubes' self-intersections where blocks overlap, dissertation section 4.2, Figures 4.6-4.8), by
// CGAL's box intersection (Box_intersection_d over the triangles' bounding boxes, closed boxes)
// and exact predicates on Exact_predicates_inexact_constructions_kernel triangles.
//
// Input: welded vertices (a vertex shared by two triangles is one index; see kernels/crack_edges.hpp
// weld_by_position), 3 indices per triangle, and per triangle a group id (the block). Only pairs of
// triangles of *different* groups are classified:
//   - same three vertices: a duplicate (coincident duplicated surface of overlapping blocks whose
//     nodes coincide), counted in `duplicates`, not as an intersection;
//   - two shared vertices (an edge): intersecting when the two other vertices are coplanar with the
//     edge and on the same side of it (the triangles overlap beyond the edge);
//   - one shared vertex p: intersecting when the edge opposite p of either triangle meets the other
//     triangle (they meet beyond p);
//   - none shared: CGAL::do_intersect of the two triangles (touching counts).
// Triangles whose three points are collinear (or repeated) are skipped and counted in `degenerate`.
// Units: any (positions are compared exactly). Cost: O((n + k) log n) for k box-overlapping pairs.
// Thread-safety: reentrant; single-threaded. Throws std::invalid_argument for inconsistent arrays
// (index out of range, group count != triangle count), std::bad_alloc.
#pragma once
#include <cstdint>
#include <span>

namespace meshless {

struct TrianglePairStats {
    std::int64_t intersecting = 0;  ///< pairs of triangles from different groups that intersect
    std::int64_t duplicates = 0;    ///< pairs from different groups with the same three vertices
    std::int64_t degenerate = 0;    ///< triangles skipped (collinear points)
    std::int64_t candidates = 0;    ///< pairs from different groups whose bounding boxes overlap
};

/// xyz: 3 coordinates per vertex; tri: 3 vertex indices per triangle; group: one id per triangle.
TrianglePairStats count_intersecting_triangle_pairs(std::span<const double> xyz, std::span<const std::uint32_t> tri,
                                                    std::span<const std::uint32_t> group);

/// The same classification over all O(n^2) pairs, without boxes (the tests' oracle for the box
/// filtering); `candidates` counts every pair of different groups.
TrianglePairStats count_intersecting_triangle_pairs_brute_force(std::span<const double> xyz,
                                                                std::span<const std::uint32_t> tri,
                                                                std::span<const std::uint32_t> group);

}  // namespace meshless
