// The depth-first binning rule of dissertation section 5.3 (kernels/scattered_binning_grid.hpp)
// over points that are not held in memory: the caller rescans them (a point store read brick by
// brick, formats/point_store.hpp) once per octree level the rule descends, and only the nodes it
// descends are kept (three 32-bit cell coordinates and eight saturating child counts each). The
// rule's nodes are the same as make_binning_grid's: a point's node at level l along a split axis is
// min(floor(u * 2^l), 2^l - 1) of its unit position u, exactly the halving of the recursive walk
// (dyadic arithmetic, no rounding), so the collected levels, their lower median and the grid are
// the same for any order of the points. Memory: O(nodes descended) <= n / 2^d (d split axes).
// Units: world bounds. Throws what make_binning_grid throws (InvalidArgument), and whatever the
// scan throws. Not thread-safe in itself (the scan may be).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <span>

#include "kernels/scattered_binning_grid.hpp"

namespace meshless {

/// Visits every point of a set, chunk by chunk, in any order (the same points on every call).
using PointScan = std::function<void(const std::function<void(std::span<const Vec3>)>& chunk)>;

/// The rule's level (the lower median of the collected levels) for the n points `scan` visits,
/// whose bounding box is `bounds`; `scans` (optional) gets the number of scans made.
int binning_rule_level_scanned(const PointScan& scan, std::uint64_t n, const std::array<Vec3, 2>& bounds,
                               const BinningGridParams& params, int* scans = nullptr);

/// make_binning_grid of the points `scan` visits (bit-identical), from their count and bounding box.
BinningGrid make_binning_grid_scanned(const PointScan& scan, std::uint64_t n, const std::array<Vec3, 2>& bounds,
                                      const BinningGridParams& params = {});

}  // namespace meshless
