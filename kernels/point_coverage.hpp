// Where scattered data actually supports a field value, and how far a value may stray from the data
// around it ("fields that do not invent data"). Meshless fields extrapolate beyond their
// data (an RBF grows away from its points) and overshoot between very unequal neighbours (the HYG
// stars' luminosities); callers that show values to a user (probe, slice, resample) pass them
// through apply().
//
// Support test: a position x is covered when
//   (a) its nearest data point p_i lies within factor * h_i, h_i being the distance from p_i to its
//       8th nearest neighbour (fewer for tiny sets): a local spacing that adapts to graded and
//       anisotropic data; or
//   (b) x is surrounded by its K = 12 nearest data points (the mean of the unit vectors from x to
//       them has length <= 0.5) and lies within 1.5 * factor * mean(h) of the nearest: a gap a little
//       wider than the local spacing inside the data is not a hole (random sets, survey lines),
//       while a void of several spacings, and anything beyond the data's edge, stays uncovered.
// Value range (with values): a value is kept within the data's range [min, max] (a clamp, so a
// continuous field stays continuous). A band from each position's nearest values was tried and
// refused: its edges jump where the neighbour set changes, and clamping to it tiled slices of the
// gravity survey with Voronoi-shaped patches and erased a real anomaly (gravi.txt).
// kNN via nanoflann (the only file that includes it). Immutable after construction; every query
// is thread-safe. Throws std::bad_alloc only; InvalidArgument when values and points differ in size.
#pragma once
#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

/// What a position outside the data's support gets (--extrapolate).
enum class Extrapolate {
    nan,      ///< NaN value and gradient: the data does not reach here (default)
    clamp,    ///< the field's value kept within the data range (the nearest data value where the field has none)
    nearest,  ///< the value of the nearest data point, gradient 0
};

struct SupportCounts {
    std::size_t uncovered = 0;  ///< positions outside the support (handled per Extrapolate)
    std::size_t clamped = 0;    ///< values moved into the data range (inside or outside the support)
};

class PointCoverage {
public:
    /// factor > 0. The points are copied. Without values, apply() only masks (Extrapolate::nan).
    PointCoverage(std::span<const Vec3> points, double factor);
    /// With the data values (same length as points; non-finite values are not expected): values are
    /// kept within their range, and Extrapolate::nearest is available.
    PointCoverage(std::span<const Vec3> points, std::span<const double> values, double factor);
    ~PointCoverage();
    PointCoverage(const PointCoverage&) = delete;
    PointCoverage& operator=(const PointCoverage&) = delete;
    bool covered(const Vec3& x) const;
    /// The points are the part of a whole set inside the box `held` (world; an axis may be
    /// unbounded) (kernels/field_region.hpp): from now on every query notes whether the
    /// neighbourhoods it reads (its nearest points, and theirs for the spacing) lie inside it, so
    /// that its answer is the whole set's; part_exact() says whether all of them did.
    void set_part_of(const std::array<Vec3, 2>& held);
    bool part_exact() const;
    /// The whole set's value range, for points that are a part of it (set_part_of): values are kept
    /// within [range[0], range[1]] instead of the given points' own range. No effect without values.
    void set_value_range(const std::array<double, 2>& range);
    /// Sets value[i] (and grad[i]) to NaN where p[i] is not covered; returns how many.
    std::size_t mask(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const;
    /// The support test, then: covered values kept within the data range (when values were given),
    /// uncovered ones handled per `mode` (clamp and nearest need values: without them, NaN).
    /// A clamped or nearest value has gradient 0. grad may be empty.
    SupportCounts apply(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad, Extrapolate mode) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace meshless
