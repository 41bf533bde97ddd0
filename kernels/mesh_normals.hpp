// Per-vertex normals of a triangle mesh without them (the naive multiblock marching cubes, whose
// vertices are welded only within a block): the sum of the normals (p1 - p0) x (p2 - p0) of the
// triangles around each vertex (so weighted by their areas), normalised. The triangles wind
// counter-clockwise seen from the side of decreasing value (VTK's convention, as the marching cubes
// here make them), so the normals point toward decreasing value too. A vertex of no triangle, or
// whose triangles' normals cancel, gets (0, 0, 0).
// Units: none (unit vectors). Shapes: xyz 3 floats per vertex, tri 3 indices per triangle; returns
// 3 floats per vertex. Throws std::out_of_range for an index beyond the vertices. Reentrant.
// Dissertation: section 4.2 (the naive per-block surfaces the meshless ones are compared with).
#pragma once
#include <vector>

#include "kernels/marching_cubes.hpp"

namespace meshless {

std::vector<float> area_weighted_normals(const Mesh& m);

}  // namespace meshless
