// Merge coincident and near-duplicate scattered points before building a meshless field
// (overlapping multiblock grids share their interface nodes; dissertation chapter 4).
// Points closer than `tolerance` (world units) to an earlier kept point are merged into it: the
// kept point keeps its position, its value becomes the mean of the merged values. Greedy in input
// order, so the result is deterministic. O(n) expected time with a hash grid of cells 4*tolerance.
// Output positions are relative to `origin` (the centre of the input bounding box), which removes
// large coordinate offsets (e.g. 1e6) before any RBF arithmetic.
// Preconditions: pos.size() == value.size(), all finite. Throws only std::bad_alloc.
// Thread-safety: pure function.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

struct MergedPoints {
    Vec3 origin;                 ///< world position of the local frame (bbox centre of the input)
    std::vector<Vec3> pos;       ///< kept points, relative to origin
    std::vector<double> value;   ///< mean value of each kept point's group
    std::uint64_t merged = 0;    ///< input points folded into an earlier one
    double tolerance = 0;        ///< world units
    Vec3 scale{1, 1, 1};         ///< per-axis factor applied to pos (1 unless a caller normalises axes)
};

/// Mean point spacing h = (prod of non-degenerate extents / n)^(1/k) (k non-degenerate axes; an
/// axis is degenerate when its extent is below 1e-9 of the largest). 0 when all points coincide.
double mean_point_spacing(std::span<const Vec3> pos);
/// The same for n points whose bounding box is `box`.
double mean_point_spacing(const std::array<Vec3, 2>& box, std::uint64_t n);

/// Merge points within `tolerance` (>= 0; 0 merges exact duplicates only).
MergedPoints merge_near_duplicates(std::span<const Vec3> pos, std::span<const double> value, double tolerance);
/// The same with the frame of a whole set that `pos` is part of (kernels/field_region.hpp): origin
/// the centre of `frame` (that set's bounding box), hash cells aligned to its lower corner (and,
/// with tolerance 0, as wide as that set's mean spacing over `frame_points` points), so a part
/// merges as the whole set does wherever a point's neighbours within the tolerance are in the part.
MergedPoints merge_near_duplicates(std::span<const Vec3> pos, std::span<const double> value, double tolerance,
                                   const std::array<Vec3, 2>& frame, std::uint64_t frame_points);

}  // namespace meshless
