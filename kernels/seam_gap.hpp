// The seam test of the multiblock/AMR isosurface (dissertation section 4.4: points seeded in
// different blocks must lie on one surface, where naive per-block surfaces crack or overlap).
//
// For every pair of output points (i, j) seeded in different blocks whose splats overlap
// (|p_i - p_j| <= max(r_i, r_j)), the gap is the distance of p_i from j's tangent plane,
// |n_j . (p_i - p_j)| with n_j j's unit normal, taken both ways. seam_gaps reports the number of such
// pairs and the largest and 99th-percentile gap, world units: two points on one smooth surface, a
// splat radius apart, are off each other's tangent planes by about r^2 kappa / 2 (kappa the
// curvature), so the gap is compared with the Newton tolerance plus that term by the caller.
// Uniform hash grid of cell size = the largest radius, 27 neighbour cells per point.
// Units: world. Points, normals, radii and blocks of one size (InvalidArgument otherwise); points with
// a non-finite position/normal/radius take no part. Reentrant, single-threaded.
#pragma once
#include <cstdint>
#include <span>

#include "kernels/vec3.hpp"

namespace meshless {

struct SeamGaps {
    std::uint64_t pairs = 0;      ///< ordered pairs (i, j) of different blocks with overlapping splats
    double max_gap = 0;           ///< world units
    double p99_gap = 0;           ///< world units
    double max_curvature_term = 0;  ///< max over pairs of |p_i - p_j|^2 / (2 R), R = the radius scale given
};

/// `curvature_radius` (> 0, world units) only feeds max_curvature_term; pass the smallest radius of
/// curvature the surface is known to have, or infinity. across = false: the same statistics over
/// pairs of one block (i != j), the reference a seam is compared with (same curvature term).
SeamGaps seam_gaps(std::span<const Vec3> pos, std::span<const Vec3> normal, std::span<const float> radius,
                   std::span<const std::uint32_t> block, double curvature_radius, bool across = true);

}  // namespace meshless
