// The trilinear interpolant of a brick store (.mlb) as a Field (dissertation Eq. 3.1 over the
// bricks of section 3.6's out-of-core layout): the same values and gradients as TrilinearField of
// the whole volume (kernels/trilinear_field.hpp: clamped to the nearest cell outside the grid), but
// the samples are read brick by brick through the byte-budgeted BrickCache, so `meshless render`
// of a store stays within --memory. Every cell belongs to exactly one brick (its ghost layer holds
// the far corners), so no evaluation needs two bricks.
// A batch is visited in its own order; runs of consecutive points in the same brick share one
// cache lookup (ray samples are coherent: a batch of 128 samples along a ray touches a few bricks).
// Also: store_value_bounds, the bricks' exact vmin/vmax from the store's index as the ray caster's
// empty-space boxes (kernels/value_bounds_grid.hpp).
// Thread-safety: evaluate() is thread-safe (the cache is; the store's reads are). The store and the
// cache must outlive the field. Throws what BrickCache::get throws (FormatError for a damaged brick,
// naming it); FormatError when the index lacks a brick of the grid.
#pragma once
#include <vector>

#include "kernels/field.hpp"
#include "kernels/value_bounds_grid.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_store.hpp"

namespace meshless {

class BrickStoreField final : public Field {
public:
    BrickStoreField(const BrickStore& store, BrickCache& cache);
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override;
    std::array<Vec3, 2> bounds() const override;
    std::string name() const override { return "trilinear"; }

private:
    const BrickStore& store_;
    BrickCache& cache_;
    std::vector<std::size_t> by_coord_;  ///< brick index of brick coordinate (x fastest)
};

/// The bricks of `store` as value-bounds boxes (exact: the ranges of their voxels, ghosts included).
ValueBoundsGrid store_value_bounds(const BrickStore& store);

}  // namespace meshless
