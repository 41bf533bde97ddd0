// Every voxel of a brick store (.mlb, ooc/brick_store.hpp) as a scattered sample (dissertation
// chapter 6 input: "each voxel a sample"), read brick by brick: one decoded brick in memory at a
// time, never the volume. Each voxel is taken once (from the brick that owns it: the ghost layer
// shared with the next brick is skipped), so the set equals point_set_from_volume() of the same
// volume up to order (here Morton brick order, x fastest inside a brick).
// NaN/Inf samples (float stores) are dropped and counted. Units: world positions from the store's
// grid, values in the store's units. Throws what BrickStore throws (FormatError naming the brick,
// IoError). Thread-safety: reentrant.
#pragma once
#include <string>

#include "kernels/point_set.hpp"

namespace meshless {

PointSet point_set_from_brick_store(const std::string& path);

}  // namespace meshless
