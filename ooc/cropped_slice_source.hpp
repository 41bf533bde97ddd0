// The slices of a crop of a volume (kernels/volume_crop.hpp) served from a source of the whole
// volume's slices, for the slab streamer (dissertation section 3.6): slice k of the crop is slice
// box.lo[2] + k of the source, its window [lo, hi] in x and y copied out. The source is told the
// window first (SliceSource::restrict_xy), so a brick store reads only the bricks the crop touches.
// Memory: the source's slices of one request (nx * ny * count samples of the whole volume).
// Throws what the source throws; InvalidArgument for a range outside the crop's slices.
// Thread-safety: one source per thread, as every SliceSource.
// Dissertation: section 3.6 (volumes bigger than RAM).
#pragma once
#include <memory>

#include "kernels/block_minmax.hpp"
#include "ooc/slice_source.hpp"

namespace meshless {

/// `box` must lie within the source's grid (crop_voxels of that grid).
std::unique_ptr<SliceSource> make_cropped_source(std::unique_ptr<SliceSource> source, const VoxelBox& box);

}  // namespace meshless
