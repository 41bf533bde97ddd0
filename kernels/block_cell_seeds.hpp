// Marching-cubes seeds of the multiblock/AMR isosurface method (dissertation section 4.4): per
// hexahedral cell of a structured block (kernels/structured_block.hpp), its marching-cubes triangles
// in physical space (kernels/hex_marching_cubes.hpp), and inside each triangle the barycentric
// lattice of n(n+1)/2 samples (kernels/barycentric_lattice.hpp), each one SeedRecord: position,
// the triangle's unit normal (pointing to decreasing values, VTK's convention), value = iso (the block interpolant is
// linear along the triangle), base radius sqrt(2A/(pi n(n+1))) (kernels/multiblock_splat_radius.hpp),
// the cell's diagonal and the block id. The seeds are then projected onto one continuous meshless
// field (stream/field_project_stage.hpp).
//
// Cells: cell (i,j,k) of a block with dims (nx,ny,nz) has corners at nodes (i+dx, j+dy, k+dz),
// dx,dy,dz in {0,1}, corner c = dx + 2dy + 4dz; cells are numbered c = i + (nx-1)(j + (ny-1)k).
// A block with a dimension of 1 has no cells. Cell-centred blocks (AMR) are contoured on their
// lattice of centres the same way.
// Skipped and counted:
//   - covered: every corner covered by a finer AMR level (StructuredBlock::covered), seeded there;
//   - invalid: a corner that is blanked (valid == 0) or has a non-finite position or value; counted
//     for every cell, whatever the isovalue;
//   - degenerate: a cell the isosurface crosses whose corner Jacobians (hex_jacobian_range) are not
//     all of the block's orientation sign: collapsed (a zero determinant), inverted (mixed signs) or
//     turned inside out against the rest of its block.
// Orientation: a block is right-handed (+1) or left-handed (-1, e.g. some PLOT3D grids) by the
// census of kernels/block_cells.hpp (block_orientation); triangles of left-handed blocks are wound the other way, so every normal points to
// decreasing values in world space. Zero-area triangles (crossings at a shared corner) give no seed
// and are counted.
// Units: world positions, the data's values. Pure and reentrant; allocates only in `out`.
// block_cell_seeds throws nothing but std::bad_alloc (preconditions are asserted); plan_block_seeds
// checks the blocks' array sizes.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/block_cells.hpp"
#include "kernels/records.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

struct BlockSeedStats {
    std::int64_t cells = 0;               ///< cells visited
    std::int64_t invalid_cells = 0;       ///< skipped: a blanked / non-finite corner
    std::int64_t degenerate_cells = 0;    ///< skipped: collapsed or inverted (crossed by the surface)
    std::int64_t covered_cells = 0;       ///< skipped: every corner covered by a finer AMR level (kernels/amr_cover.hpp)
    std::int64_t active_cells = 0;        ///< cells that produced triangles
    std::int64_t triangles = 0;           ///< triangles with a positive area
    std::int64_t zero_area_triangles = 0; ///< triangles skipped for a zero area
    std::int64_t seeds = 0;               ///< seeds written
    BlockSeedStats& operator+=(const BlockSeedStats& o) {
        cells += o.cells; invalid_cells += o.invalid_cells; degenerate_cells += o.degenerate_cells; covered_cells += o.covered_cells;
        active_cells += o.active_cells; triangles += o.triangles; zero_area_triangles += o.zero_area_triangles;
        seeds += o.seeds;
        return *this;
    }
};

/// What the seed stage and the framing need before the run, from one pass over every block.
struct BlockSeedPlan {
    std::vector<int> orientation;               ///< per block, +1 / -1
    std::vector<std::int64_t> first_cell;       ///< per block, its first global cell index; size blocks + 1
    std::array<double, 2> value_range{0, 0};    ///< over valid nodes; {NaN, NaN} when none
    std::int64_t active_cells = 0;              ///< cells with all corners valid crossed by iso
    std::array<Vec3, 2> active_bounds{};        ///< union of the corners of those cells
    std::array<Vec3, 2> node_bounds{};          ///< union of the valid nodes
    std::int64_t total_cells() const { return first_cell.empty() ? 0 : first_cell.back(); }
};

/// One serial pass over mb. A cell is crossed when some corner value >= iso and some < iso.
/// Throws InvalidArgument when a block's arrays do not match its dims (block_cell_seeds relies on
/// the plan having checked them).
BlockSeedPlan plan_block_seeds(const Multiblock& mb, double iso);

/// Appends the seeds of cells [c0, c1) of block `b` (local cell indices, 0 <= c0 <= c1 <=
/// block_cell_count(b)) to `out`, in cell order, then triangle order, then lattice order, and adds
/// the counts to `st`. `lattice` = barycentric_lattice(n).
void block_cell_seeds(const StructuredBlock& b, std::uint32_t block_id, int orientation, std::int64_t c0, std::int64_t c1,
                      double iso, int n, std::span<const std::array<double, 3>> lattice, std::vector<SeedRecord>& out,
                      BlockSeedStats& st);

}  // namespace meshless
