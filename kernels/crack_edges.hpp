// Crack edges of a multiblock triangle mesh (the naive per-block marching cubes of dissertation
// section 4.2, Figures 4.6-4.8: "cracks" where blocks meet).
//
// Definitions (also in `meshless mc --help`):
//   - weld_by_position: vertices whose float positions are bitwise equal (-0 and +0 equal) become
//     one vertex, across blocks too; vertex order = first appearance. A triangle whose welded
//     vertices are not three distinct ones is degenerate (no edges).
//   - an edge is an unordered pair of welded vertices of a non-degenerate triangle; a boundary edge
//     is an edge of exactly one triangle; a non-manifold edge one of three or more (e.g. where the
//     duplicated surfaces of overlapping blocks with coincident nodes meet).
//   - a crack edge is a boundary edge whose midpoint lies inside the data domain, i.e. not on the
//     outer boundary of the data: inside a cell (all corners valid) of a block *other than the
//     edge's own block* (`inside_other(midpoint, own_block)`, e.g. BlockCellLocator of
//     kernels/hex_point_location.hpp). The own block is left out because a boundary edge always lies
//     on the boundary of its own block's contoured cells (a block face, or the face of a skipped
//     cell); holes at skipped cells of a block that no other block covers are reported as skipped
//     cells, not as cracks.
// Units: world. Thread-safety: reentrant; single-threaded (inside_other is called serially).
// Throws std::invalid_argument for inconsistent arrays, what inside_other throws, std::bad_alloc.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "kernels/marching_cubes.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct WeldedMesh {
    std::vector<double> xyz;           ///< 3 per welded vertex (the float positions, exactly)
    std::vector<std::uint32_t> tri;    ///< 3 welded indices per triangle (same triangles, same order)
    std::vector<std::uint32_t> block;  ///< per triangle (copied; zeros when the mesh has none)
};

WeldedMesh weld_by_position(const Mesh& m);

struct CrackEdgeStats {
    std::int64_t vertices = 0;              ///< welded vertices
    std::int64_t degenerate_triangles = 0;  ///< triangles with a repeated welded vertex
    std::int64_t edges = 0;
    std::int64_t boundary_edges = 0;
    std::int64_t nonmanifold_edges = 0;
    std::int64_t crack_edges = 0;
};

struct BoundaryEdge {
    Vec3 midpoint;
    std::uint32_t block = 0;  ///< the block of the edge's triangle
};

/// Every count of CrackEdgeStats but crack_edges, and the boundary edges (in (a, b) vertex order).
CrackEdgeStats edge_census(const WeldedMesh& m, std::vector<BoundaryEdge>& boundary);

/// edge_census, then crack_edges = the boundary edges for which inside_other(midpoint, block).
CrackEdgeStats count_crack_edges(const WeldedMesh& m,
                                 const std::function<bool(const Vec3& midpoint, std::uint32_t own_block)>& inside_other);

}  // namespace meshless
