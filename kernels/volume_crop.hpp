// Crops of a regular volume by a box in world units (`--crop X0,Y0,Z0,X1,Y1,Z1` of the volume
// commands): the samples whose world positions lie in the box, inclusive, as a volume of their own
// whose origin is the first of them, so the cropped volume's sample (i, j, k) sits where the full
// volume's (lo + i, lo + j, lo + k) does (no resampling).
// Units: world units of the grid (origin + index * spacing). Shapes: a VoxelBox is inclusive sample
// indices (kernels/block_minmax.hpp). Throws InvalidArgument (a usage error: the box is the
// caller's) for a box that is not six finite numbers with lo <= hi, or that leaves fewer than 2
// samples along an axis (no cell), naming `name` and the axis.
// Thread-safety: pure functions, reentrant.
// Dissertation: none (an everyday operation on chapter 3 input volumes).
#pragma once
#include <array>
#include <string>

#include "kernels/block_minmax.hpp"
#include "kernels/grid.hpp"

namespace meshless {

/// The samples of `g` inside the world box {x0, y0, z0, x1, y1, z1}.
VoxelBox crop_voxels(const GridSpec& g, const std::array<double, 6>& world, const std::string& name);

/// The grid of the samples of `box`: its dims, the same spacing, origin at sample box.lo.
GridSpec cropped_grid(const GridSpec& g, const VoxelBox& box);

/// The samples of `box` copied out of `v` (x fastest).
Volume crop_volume(const Volume& v, const VoxelBox& box);

}  // namespace meshless
