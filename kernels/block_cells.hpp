// The hexahedral cells of a structured block (kernels/structured_block.hpp), as the marching-cubes
// seed stage (kernels/block_cell_seeds.hpp, dissertation section 4.4) and the naive per-block
// marching cubes (kernels/block_marching_cubes.hpp, Figures 4.6-4.8) both walk them.
//
// Cell (i,j,k), 0 <= i < dims[0]-1 (etc.), has corner c = dx + 2dy + 4dz at node (i+dx, j+dy, k+dz).
// A cell is usable when every corner is valid (StructuredBlock::valid) with a finite position and
// value. Its orientation is the sign of its corner Jacobians (kernels/hex_marching_cubes.hpp
// hex_jacobian_range): +1 / -1 when all eight are of one strict sign, 0 when collapsed or inverted.
// A block is left-handed (e.g. some PLOT3D grids) when more of its usable cells are negative than
// positive (the census; ties: right-handed); its triangles are then wound the other way so that
// every block's normals point to decreasing values (VTK's convention) in world space.
// Units: world positions. Pure, reentrant, no allocation; throws nothing.
#pragma once
#include <array>
#include <cstdint>

#include "kernels/hex_marching_cubes.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

/// Cells of a block: prod(max(0, dims[a] - 1)).
std::int64_t block_cell_count(const StructuredBlock& b);

/// Gathers cell (i,j,k) into `cell` and its corner node indices into `node`; false when a corner is
/// invalid or not finite (cell/node are then partly written).
bool gather_block_cell(const StructuredBlock& b, std::int64_t i, std::int64_t j, std::int64_t k, HexCell& cell,
                       std::array<std::int64_t, 8>& node);

/// +1 / -1 for a cell whose corner Jacobians are all of one strict sign, 0 for a collapsed or
/// inverted cell.
int hex_jacobian_sign(const HexCell& cell);

struct BlockOrientation {
    std::int64_t positive = 0;    ///< usable cells with all corner Jacobians > 0
    std::int64_t negative = 0;    ///< usable cells with all corner Jacobians < 0
    std::int64_t degenerate = 0;  ///< usable cells with a zero or mixed-sign Jacobian
    std::int64_t invalid = 0;     ///< cells with an invalid corner
    bool left_handed() const { return negative > positive; }
    BlockOrientation& operator+=(const BlockOrientation& o) {
        positive += o.positive;
        negative += o.negative;
        degenerate += o.degenerate;
        invalid += o.invalid;
        return *this;
    }
};

/// One pass over the block's cells (or the cell layers [k0, k1), clamped): sums over layer ranges
/// equal the whole.
BlockOrientation block_orientation(const StructuredBlock& b);
BlockOrientation block_orientation(const StructuredBlock& b, std::int64_t k0, std::int64_t k1);

}  // namespace meshless
