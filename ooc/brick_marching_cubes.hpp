// Marching cubes over a brick store (the section-3.6 baseline, out of core): each active brick
// (BrickIndex) is read through the byte-budgeted cache and triangulated alone; vertices on the faces
// two bricks share are computed with global indices (bitwise identical in both bricks) and welded,
// so the mesh is as closed as the in-memory one. Only the input is bounded by the cache budget; the
// mesh is held in memory. Difference to the in-memory mesh: normals of the welded seam vertices use
// one-sided differences across the seam (a brick has no ghost layer below its first voxel), and
// vertex/triangle order follows the bricks' Morton order. Throws what the store and cache throw.
#pragma once
#include "kernels/marching_cubes.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_index.hpp"

namespace meshless {

Mesh marching_cubes_bricks(const BrickStore& store, BrickCache& cache, const BrickIndex& index, double iso,
                           McStats* stats = nullptr);

}  // namespace meshless
