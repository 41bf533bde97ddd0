// A brick store read back as z-slices (dissertation section 3.6, out of core): so that every command
// that takes a VOLUME also takes a .mlb — convert (re-bricking), synth, sample, info --range. Slices
// are assembled from one layer of bricks at a time (memory: one brick layer, never the volume);
// read_slices must be called with increasing, contiguous k (the SliceSource contract). Throws what
// BrickStore::read_brick throws (FormatError naming a damaged brick).
#pragma once
#include <memory>
#include <string>

#include "ooc/brick_store.hpp"
#include "ooc/slice_source.hpp"

namespace meshless {

std::unique_ptr<SliceSource> open_brick_store_slices(const std::string& path);

/// The whole volume of a store in memory (for commands that need it whole; memory = the volume).
Volume read_brick_store_volume(const std::string& path);

}  // namespace meshless
