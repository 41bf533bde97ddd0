// A meshless field built part by part (docs/architecture.md, "Fields out of core"): the numbers a
// field takes from the whole point set (FieldFrame) and the part of space one build answers for
// (FieldRegion). A field built over the points of a region's loaded box with the whole set's frame
// evaluates, anywhere in the region's query box, to the same bits as the field built over every
// point, as long as every point list the build reads lies inside the loaded box: MpuField checks
// that as it builds (MpuField::region_exact) and the caller widens the loaded box when it does not
// hold. Units: world. Plain data; FieldFrameBuilder is not thread-safe (one per scan).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>

#include "kernels/flat_hull.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

/// What a field takes from the whole point set: its bounding box (the frame's origin and axis
/// scales, the MPU root cube, Hardy's c, the mean spacing with `points` and so the merge
/// tolerance), and whether every point lies in one plane or line (an MPU flat leaf then looks for
/// no points off its plane). Computed by FieldFrameBuilder over the points in input order.
struct FieldFrame {
    std::array<Vec3, 2> bounds{};
    std::uint64_t points = 0;
    bool data_flat = false;
};

/// The frame of a point set scanned in order, chunk by chunk (the same bits as one pass over all).
class FieldFrameBuilder {
public:
    void add(std::span<const Vec3> pos);
    FieldFrame finish() const;

private:
    std::array<Vec3, 2> bounds_{};
    std::uint64_t n_ = 0;
    PointMoments moments_;
};

/// The frame of `pos` in one pass.
FieldFrame field_frame_of(std::span<const Vec3> pos);

/// One part of a field: the whole set's frame, the box whose queries this part answers (query),
/// and the box whose points it was given (loaded: every point of the whole set inside it, none
/// outside; an axis may be unbounded, +-infinity). query must lie inside loaded.
struct FieldRegion {
    FieldFrame frame;
    /// Optional counts of the whole set's points in a world ball (centre, radius), from an index of
    /// the data that is not the points (a point store's cell counts): `missing`, an upper bound on
    /// those that were not given (0 only when none), and `present`, a lower bound on those there are. Without them a list reaching beyond `loaded` is inexact; with them only
    /// one that may lack points, and an octree node whose ball surely holds more than the MPU's N
    /// points is split as in the whole set even when few of them were given.
    std::function<std::uint64_t(const Vec3& centre, double radius)> missing, present;
    std::array<Vec3, 2> query{};
    std::array<Vec3, 2> loaded{Vec3{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                                    -std::numeric_limits<double>::infinity()},
                               Vec3{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                                    std::numeric_limits<double>::infinity()}};
    /// The most heap the fitted field may take, bytes (0: no limit): a build whose octree shows a
    /// larger field stops before the local fits (MpuField::over_budget), as the caller's budget asks.
    std::uint64_t max_field_bytes = 0;
};

}  // namespace meshless
