// Coarse span-space summary of a regular volume: the minimum and maximum of the finite samples in
// cubic blocks of B x B x B cells (dissertation sections 2.3 and 3.6: the interval of a block of
// cells decides whether an isosurface can cross it, before any cell is visited).
//
// Blocks are aligned exactly like the bricks of a brick store with edge B (ooc/brick_store.hpp):
// block (bx, by, bz) holds the voxels [b*B, min(b*B + B, n - 1)] on each axis, so neighbouring
// blocks share a voxel layer, and there are max(1, ceil((n - 1) / B)) blocks per axis. A block is
// active for iso when vmin < iso <= vmax (the brick-index rule, ooc/brick_index.hpp), so the
// surface box of a volume in memory equals the union of the active bricks of its brick store.
//
// Cost: one pass over the samples (each voxel read once per row segment it belongs to, about
// (B+1)/B times), no allocation beyond 2 doubles per block. Thread-safety: pure functions.
// Throws nothing but std::bad_alloc.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "kernels/grid.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct BlockMinMax {
    int edge = 32;
    std::array<std::int64_t, 3> blocks{0, 0, 0};  ///< blocks per axis
    std::vector<double> vmin, vmax;               ///< per block, x fastest; NaN when no finite sample
    /// Minimum and maximum over all finite samples (= Volume::value_range()); {NaN, NaN} if none.
    std::array<double, 2> range() const;
};

/// Per-block min/max of v with blocks of `edge` cells (edge >= 1).
BlockMinMax block_minmax(const VolumeView& v, int edge = 32);

/// The same summary built from z-slices as they are read (a volume streamed slab by slab needs one
/// slab in memory, not the volume): add every slice of the grid once, in any order and grouping,
/// then finish() gives exactly block_minmax() of the whole volume.
class BlockMinMaxBuilder {
public:
    BlockMinMaxBuilder(const GridSpec& g, SampleType type, int edge = 32);
    /// data: `count` consecutive z-slices starting at k0, samples of `type`, x fastest.
    void add_slices(std::int64_t k0, std::int64_t count, const std::byte* data);
    BlockMinMax finish() &&;

private:
    GridSpec grid_;
    SampleType type_;
    BlockMinMax out_;
};

/// Inclusive voxel-index box.
struct VoxelBox {
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{0, 0, 0};
};

/// Union of the voxel boxes of the blocks active for iso; nullopt when none is active.
std::optional<VoxelBox> active_block_box(const BlockMinMax& b, const GridSpec& g, double iso);

/// World bounds of a voxel box on grid g: origin + index * spacing.
std::array<Vec3, 2> world_bounds(const GridSpec& g, const VoxelBox& box);

}  // namespace meshless
