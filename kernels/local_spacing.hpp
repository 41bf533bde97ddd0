// The point spacing of one local fit: the mean distance from each of its points to its nearest
// other point (brute force over the local's points; a local holds at most a few hundred).
//
// Used to size Hardy's multiquadric constant c to the local fit rather than to the whole data
// (kernels/field_params.hpp, hardy_c_local): the condition number of a multiquadric system grows
// steeply with c / spacing (dissertation section 2.1.1; Fornberg and Wright's flat limit), so a c
// tied to the bounding box makes every local of a dense set ill-conditioned (3 M samples of a CT:
// 42 % of the MPU locals needed a ridge). The local spacing keeps c / spacing bounded at any density.
//
// Units: those of pos (the caller's frame). Shapes: idx indexes pos. Cost: idx.size()^2 / 2
// distance evaluations, packet-wide over a per-thread structure-of-arrays copy of the points.
// Returns 0 for fewer than two points or when every point coincides.
// Thread-safety: thread-safe (its scratch is per thread). Throws only std::bad_alloc.
#pragma once
#include <cstdint>
#include <span>

#include "kernels/vec3.hpp"

namespace meshless {

double mean_neighbour_spacing(std::span<const Vec3> pos, std::span<const std::uint32_t> idx);

}  // namespace meshless
