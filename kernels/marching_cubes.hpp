// Marching cubes (Lorensen & Cline 1987): the triangle-mesh baseline of dissertation §3.6 and the
// reference surface of the tests. Case table: kernels/marching_cubes_table.hpp (generated, faces
// resolved by "above corners are separated", so the mesh of a closed isosurface is closed and
// consistently oriented).
//
// Input: a VolumeView in its native sample type (u8/i16/u16/f32), any dims (dims < 2 on some axis
// gives an empty mesh), 64-bit indexing. A corner is above when value >= iso.
// Output (Mesh):
//   xyz      3 floats per vertex, world units: origin + spacing * (grid index + t * edge direction),
//            t = (iso - v0) / (v1 - v0) on the grid edge.
//   normals  3 floats per vertex, VTK's convention -grad f / |grad f| (towards decreasing value, out
//            of the region >= iso): per-sample gradient by central differences (one-sided at the
//            volume border or next to a non-finite neighbour), in value per world unit, interpolated
//            linearly along the edge with t, normalised and negated; where that is zero, the edge
//            direction towards the below end.
//   tri      3 vertex indices per triangle, counter-clockwise seen from the normal side, the below
//            side (normal by right-hand rule points towards decreasing value, as the vertex normals):
//            a closed surface around high values has positive signed volume.
//   Every grid edge crossing is exactly one vertex (shared by all cells around the edge).
//   Vertex and triangle order is deterministic (cells in x-fastest order).
// Cells with a NaN/Inf corner produce nothing and are counted in McStats::skipped_nonfinite;
// active_cells counts finite cells with at least one triangle. stats (when given) is overwritten.
// Memory besides the output: 5 uint32 edge-index arrays and 3 byte masks of one z-slice.
// Throws InvalidArgument for a non-finite iso, std::length_error when the mesh would need more than
// 2^32-1 vertices (uint32 indices). Reentrant; single-threaded (threads may each run a slab).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/grid.hpp"

namespace meshless {

struct Mesh {
    std::vector<float> xyz;
    std::vector<float> normals;
    std::vector<std::uint32_t> tri;  ///< 3 indices per triangle
    std::vector<std::uint32_t> block;  ///< empty, or per triangle the id of the block it came from
                                       ///< (naive multiblock marching cubes, kernels/block_marching_cubes.hpp)

    std::size_t vertex_count() const { return xyz.size() / 3; }
    std::size_t triangle_count() const { return tri.size() / 3; }
    /// Bytes held by the three arrays (sizes, not capacities).
    std::size_t memory_bytes() const {
        return xyz.size() * sizeof(float) + normals.size() * sizeof(float) +
               (tri.size() + block.size()) * sizeof(std::uint32_t);
    }
};

struct McStats {
    std::int64_t active_cells = 0;       ///< finite cells that produced triangles
    std::int64_t skipped_nonfinite = 0;  ///< cells with a NaN/Inf corner (no triangles)
};

/// Isosurface of the whole volume.
Mesh marching_cubes(const VolumeView& v, double iso, McStats* stats = nullptr);

/// Cells with cell index k in [k0, k1) (clamped to [0, nz-1)); the mesh of the whole volume is the
/// concatenation of slabs (indices offset by the earlier vertex counts) except that vertices on the
/// z-slices shared by two slabs appear once in each slab, with bitwise identical positions and
/// normals. For running slabs on several threads.
/// index_offset: for a view of part of a volume (a brick) whose grid origin is the whole volume's
/// origin, positions are origin + spacing * (index_offset + index + t): the same arithmetic as for
/// the whole volume, so vertices on faces shared by two parts are bitwise identical.
/// edge_keys (when given): resized to vertex_count(); per vertex, the key of the grid edge it lies on,
/// in the grid of dims `whole_dims` (the whole volume's, for a part of it): with (i, j, k) the
/// edge's lower end in whole-volume indices (index_offset + local) and axis 0/1/2,
///   key = 3 * (i + W0 * (j + W1 * k)) + axis.
/// Two parts of one volume give the same key to a vertex of the same edge: the stage graph welds
/// slabs and bricks by it (stream/marching_cubes_stage.hpp).
Mesh marching_cubes_slab(const VolumeView& v, double iso, std::int64_t k0, std::int64_t k1,
                         McStats* stats = nullptr, const std::array<std::int64_t, 3>& index_offset = {0, 0, 0},
                         std::vector<std::uint64_t>* edge_keys = nullptr,
                         const std::array<std::int64_t, 3>& whole_dims = {0, 0, 0});

/// The key of marching_cubes_slab's edge_keys, and its inverse.
inline std::uint64_t mc_edge_key(std::int64_t i, std::int64_t j, std::int64_t k, int axis,
                                 const std::array<std::int64_t, 3>& whole_dims) {
    return 3 * static_cast<std::uint64_t>(i + whole_dims[0] * (j + whole_dims[1] * k)) + static_cast<std::uint64_t>(axis);
}

}  // namespace meshless
