// Trilinear values of a brick store at scattered world positions (dissertation Eq. 3.1), without the
// volume in memory and without a cache miss a position: the positions are grouped by the brick whose
// cells hold them (the brick's Morton key, the store's file order) and evaluated in that order by
// BrickStoreField (ooc/brick_field.hpp), which looks a brick up once a run of positions in it, so a
// call over N random positions costs one pass over the bricks they meet. The values are the field's,
// bit for bit those of TrilinearField over the whole volume, each written at its position's index.
// Units: world coordinates. Memory: 48 bytes a position (the grouping and the grouped copies).
// Throws what BrickStoreField::evaluate throws (FormatError naming a damaged or missing brick).
// Not thread-safe across calls sharing the field's cache only as BrickCache is (it is).
#pragma once
#include <span>

#include "kernels/vec3.hpp"
#include "ooc/brick_field.hpp"

namespace meshless {

/// value[i] = field's value at p[i] (value.size() == p.size()); store: the field's store.
void brick_store_values(const BrickStore& store, const BrickStoreField& field, std::span<const Vec3> p, std::span<double> value);

}  // namespace meshless
