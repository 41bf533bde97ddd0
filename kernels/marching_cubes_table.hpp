// Marching cubes case table (dissertation §3.6: the marching cubes baseline iso-splatting is compared
// against), GENERATED at compile time from first principles (no typed-in table):
//   for each of the 256 cases and each of the 6 cell faces, the edge crossings are joined by segments;
//   an ambiguous face (above corners on one diagonal, below on the other) is resolved by a fixed rule
//   that depends only on the face's 4 corner signs, "above corners are separated" (each above corner
//   is cut off by its own segment), so the two cells sharing a face always agree and meshes are
//   closed; the segments are chained into closed polygons and every polygon is triangulated as a fan
//   from the first vertex whose diagonals do not lie in a cell face (ear clipping with that rule when
//   no such apex exists): a diagonal in a face could overlap the neighbour cell's triangles.
//   No interior (tunnel) test: polygons follow the face segments only. At most 5 triangles per case.
//
// Conventions.
//   Corner c = dx + 2*dy + 4*dz at offset (dx,dy,dz) in {0,1}^3 from the cell's lowest sample.
//   A corner is "above" when value >= iso (a NaN is never above); case = sum of (1 << c) over above
//   corners.
//   Edge e = 4*axis + b with axis 0 = x, 1 = y, 2 = z and b packing the two other offsets, lower axis
//   in bit 0:   x-edges (0..3): b = dy + 2*dz;  y-edges (4..7): b = dx + 2*dz;  z-edges (8..11): b = dx + 2*dy.
//   Explicitly: e0 0-1, e1 2-3, e2 4-5, e3 6-7, e4 0-2, e5 1-3, e6 4-6, e7 5-7, e8 0-4, e9 1-5,
//   e10 2-6, e11 3-7 (corner pairs, the lower-offset corner first).
//   Orientation (VTK's convention, as vtkMarchingCubes / vtkFlyingEdges3D): triangle (a,b,c) has
//   normal (b-a) x (c-a) (right-hand rule) pointing towards the below side, i.e. against the
//   gradient (towards decreasing value, out of the region >= iso), for a right-handed grid with
//   positive spacing: a closed surface around high values has positive signed volume.
// Thread-safety: the table is an immutable constant. Nothing here throws.
#pragma once
#include <array>
#include <cstdint>

namespace meshless {

/// Upper bound on triangles per case used for storage; McTable::max_triangles is the actual maximum.
inline constexpr int kMcMaxTriangles = 6;  // the generated table needs 5

struct McCase {
    std::uint8_t triangle_count = 0;
    std::uint8_t polygon_count = 0;
    std::uint8_t ambiguous_faces = 0;  ///< faces of this case resolved by the separation rule
    std::uint16_t edge_mask = 0;       ///< bit e set when edge e has a sign change
    std::array<std::uint8_t, 3 * kMcMaxTriangles> edges{};  ///< 3 edge numbers per triangle
};

struct McTable {
    std::array<McCase, 256> cases{};
    int max_triangles = 0;
};

/// The generated table (a compile-time constant; returning a reference is free).
const McTable& marching_cubes_table();

/// Corner pair of every edge, lower-offset corner first.
inline constexpr std::array<std::array<int, 2>, 12> kMcEdgeCorners{{
    {0, 1}, {2, 3}, {4, 5}, {6, 7},   // x
    {0, 2}, {1, 3}, {4, 6}, {5, 7},   // y
    {0, 4}, {1, 5}, {2, 6}, {3, 7},   // z
}};

/// The 6 faces: corners in cyclic order, then the outward normal axis (0..2) and sign (-1/+1).
struct McFace {
    std::array<int, 4> corners;
    int axis;
    int sign;
};
inline constexpr std::array<McFace, 6> kMcFaces{{
    {{0, 2, 6, 4}, 0, -1}, {{1, 3, 7, 5}, 0, +1},
    {{0, 1, 5, 4}, 1, -1}, {{2, 3, 7, 6}, 1, +1},
    {{0, 1, 3, 2}, 2, -1}, {{4, 5, 7, 6}, 2, +1},
}};

/// Edge joining two corners that differ in exactly one offset bit.
constexpr int mc_edge_of(int a, int b) {
    const int d = a ^ b;
    const int lo = a < b ? a : b;
    if (d == 1) return lo >> 1;
    if (d == 2) return 4 + ((lo & 1) | ((lo >> 2) << 1));
    return 8 + (lo & 3);
}

/// True when cube edges a and b lie on a common face.
constexpr bool mc_edges_share_face(int a, int b) {
    for (const McFace& f : kMcFaces) {
        bool ha = false, hb = false;
        for (int k = 0; k < 4; ++k) {
            const int e = mc_edge_of(f.corners[k], f.corners[(k + 1) % 4]);
            ha = ha || e == a;
            hb = hb || e == b;
        }
        if (ha && hb) return true;
    }
    return false;
}

}  // namespace meshless
