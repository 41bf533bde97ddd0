// Marching cubes of one hexahedral cell in physical space (dissertation section 4.4: each block's
// marching-cubes triangles are the seeds of the multiblock method, and per-block marching cubes is
// the naive baseline of Figures 4.6-4.8). The cell is any hexahedron of a structured block,
// curvilinear or not; the case table is kernels/marching_cubes_table.hpp's (corner c = dx + 2dy +
// 4dz in the block's (i,j,k) index offsets). An edge crossing is placed at
//   p = a + t (b - a),  t = (iso - v_a) / (v_b - v_a),
// with a the edge's lower-offset corner, so two cells of one block that share an edge compute
// bit-identical crossings. Triangle (p0,p1,p2) has normal (p1-p0) x (p2-p0) pointing to decreasing
// values (VTK's convention) when the cell is right-handed (positive Jacobian); hex_marching_cubes
// flips the winding when asked (left_handed), so callers orient every block alike.
//
// hex_jacobian_range: the determinants of the three edge vectors at each of the 8 corners (the
// trilinear map's Jacobian there, in world units^3 per unit cell): a cell whose determinants are not
// all of one strict sign is collapsed (some 0) or inverted (mixed signs), and is skipped and counted
// by the callers.
// Units: world positions, the data's values. Preconditions: finite corners and values (callers skip
// cells with a blanked or NaN corner). Pure, reentrant, no allocation, throws nothing.
#pragma once
#include <array>

#include "kernels/marching_cubes_table.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct HexCell {
    std::array<Vec3, 8> corner;    ///< world positions, index dx + 2*dy + 4*dz
    std::array<double, 8> value;   ///< values at the corners
};

struct HexTriangle {
    std::array<Vec3, 3> v;
};

/// Writes the cell's triangles at `iso` to out[0..n) and returns n (0..kMcMaxTriangles). A corner is
/// above when value >= iso (the table's rule).
int hex_marching_cubes(const HexCell& cell, double iso, bool left_handed, std::array<HexTriangle, kMcMaxTriangles>& out);

/// {min, max} of the 8 corner Jacobian determinants.
std::array<double, 2> hex_jacobian_range(const std::array<Vec3, 8>& corner);

}  // namespace meshless
