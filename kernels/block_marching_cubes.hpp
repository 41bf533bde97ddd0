// Naive per-block marching cubes of a multiblock grid (dissertation section 4.2, Figures 4.6-4.8:
// the baseline whose cracks and intersections the meshless method removes). Each block is
// contoured on its own trilinear interpolant, cell by cell (kernels/hex_marching_cubes.hpp), in
// physical space; nothing is shared between blocks.
//
// Cells: cell (i,j,k) has corners node(i+dx, j+dy, k+dz), corner c = dx + 2dy + 4dz. A cell is
//   skipped (no triangles, counted) when a corner is invalid (StructuredBlock::valid, or a non-finite
//   position/value): skipped_invalid, counted for every cell; or, when the isosurface crosses it,
//   when its corner Jacobians (hex_jacobian_range) are not all of one strict sign (collapsed or
//   inverted): skipped_degenerate (a hole in the naive surface). Every other cell is contoured.
// Orientation: block_orientation (kernels/block_cells.hpp) counts every valid cell by Jacobian sign;
//   a left-handed block is contoured with flipped winding, so every block's triangles face
//   decreasing values (VTK's convention: counter-clockwise seen from the low side, positive signed
//   volume around high values).
// Vertices: one per block edge crossed (welded within the piece by the edge's key
//   3 * node(i,j,k) + axis, the edge's lower node and axis 0/1/2), positions as hex_marching_cubes
//   computes them (bit-identical for the cells sharing the edge), stored as float.
// Units: world positions; values in the data's units. Shapes: cell layers k in [k0, k1) of
//   [0, dims[2]-1); a block with a dimension < 2 has no cells.
// Throws nothing but std::bad_alloc / std::length_error (more than 2^32-1 vertices in a piece).
// Pure and reentrant; single-threaded (the stage graph runs pieces in parallel).
#pragma once
#include <cstdint>
#include <vector>

#include "kernels/block_cells.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

struct BlockMcStats {
    std::int64_t cells = 0;               ///< cells visited
    std::int64_t active_cells = 0;        ///< contoured cells that produced triangles
    std::int64_t skipped_invalid = 0;     ///< cells with an invalid (blanked / NaN) corner
    std::int64_t skipped_degenerate = 0;  ///< collapsed or inverted cells the isosurface crosses
};

/// Marching cubes of the cell layers [k0, k1) (clamped) of block `b`. Returns the piece (local
/// indices, no normals; Mesh::block = block_id for every triangle); edge_keys[v] = the block edge key
/// of vertex v. Adds to stats.
Mesh block_marching_cubes(const StructuredBlock& b, double iso, bool left_handed, std::int64_t k0, std::int64_t k1,
                          std::uint32_t block_id, BlockMcStats& stats, std::vector<std::uint64_t>& edge_keys);

}  // namespace meshless
