// AMR hierarchies without dual grids (dissertation chapter 4 applied to AMR): which data a
// finer level supersedes, and the seed lattices of cell-centred boxes.
//
// block_extent: the region a block's data describes, axis-aligned: for a cell-centred block
//   (StructuredBlock::cell_centred, an AMR box or CellData) its cell centres' bounds grown by half
//   the spacing along each axis (the box itself); for node data the nodes' bounds. The spacing of an
//   axis is the distance between its first two nodes; an axis with a single cell takes the smallest
//   spacing of the other axes (AMR cells are boxes of one refinement level).
// mark_amr_covered: every valid node of a block at level L that lies in the extent of a block at a
//   level > L (closed box, relative tolerance 1e-9 of the extent) is marked covered: the finest data
//   wins, as ParaView/VisIt blank covered cells (vtkGhostType HIDDENCELL). to_point_set leaves
//   covered nodes out of the field. Returns the number of nodes marked; a multiblock without levels
//   above 0 is left alone.
// amr_seed_blocks: the blocks the seed stage contours. A cell-centred block is padded to its box
//   faces with one more node layer on each side (dims + 2): positions and values extrapolated
//   linearly from the two nearest centres (p_face = 1.5 p0 - 0.5 p1; a single centre: its value,
//   positions half a spacing out), valid where both sources are, so neighbouring boxes' lattices meet
//   at their shared face and reach the domain boundary: no seam or boundary band is left unseeded.
//   Covered flags are recomputed on the padded nodes; a cell whose corners are all covered is not
//   seeded (finer boxes seed it). Node-centred blocks are copied as they are. These extrapolated
//   nodes are seeds only, never field data.
// Units: world positions. Pure; allocates the returned blocks. Throws nothing but std::bad_alloc.
#pragma once
#include <array>
#include <cstdint>

#include "kernels/structured_block.hpp"

namespace meshless {

std::array<Vec3, 2> block_extent(const StructuredBlock& b);

std::uint64_t mark_amr_covered(Multiblock& mb);

/// True when some block is cell-centred (the seed stage then contours amr_seed_blocks(mb)).
bool has_cell_centred_blocks(const Multiblock& mb);

Multiblock amr_seed_blocks(const Multiblock& mb);

}  // namespace meshless
