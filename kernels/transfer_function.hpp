// Transfer function of direct volume rendering (dissertation section 6.6, Figure 6.6, and section
// 7.4): a map from a scalar value to colour (r, g, b) and opacity a, piecewise linear between
// control points.
//
// Units: values in the data's units; r, g, b, a in [0, 1]. The opacity a is the opacity of a slab
// one *reference step* thick (RayCastParams::ref_step in kernels/ray_caster.hpp): the ray caster
// corrects it for its actual step, a' = 1 - (1 - a)^(step / ref_step), so the picture does not
// depend on the sampling rate.
// Control points are sorted by value, non-decreasing (two points with the same value make a step:
// at that value and above, the later one applies). Below the first and above the last point the
// end points' colour and opacity hold (clamping). NaN maps to fully transparent black.
// Presets (transfer_function_preset) are defined over fractions t in [0, 1] of a value range
// [lo, hi] (the data's by default) and scaled to it:
//   grey     grey ramp: colour t, opacity 0.5 t                 (everything visible, fog-like)
//   viridis  matplotlib's viridis colours, opacity 0.5 t
//   ct-bone  transparent below t = 0.55, bone white, opaque above t = 0.7
//   ct-skin  soft tissue (t 0.25-0.45) in translucent skin tones + bone (t > 0.6) in white
// Throws InvalidArgument (empty, non-finite, unsorted or out-of-range points naming the index;
// unknown preset; lo >= hi for a preset). Immutable value type, thread-safe to share.
#pragma once
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace meshless {

struct TransferPoint {
    double value = 0;
    double r = 0, g = 0, b = 0, a = 0;
};

class TransferFunction {
public:
    /// Validates `points` (at least one; finite values, non-decreasing; components in [0, 1]).
    explicit TransferFunction(std::vector<TransferPoint> points);
    /// {r, g, b, a} at v (piecewise linear, clamped at the ends; NaN: {0, 0, 0, 0}).
    std::array<double, 4> at(double v) const;
    /// The largest opacity over the values [lo, hi]: the empty-space test of the ray
    /// caster (0: a region whose values all lie in [lo, hi] contributes nothing). Exact for the
    /// piecewise-linear function (its maximum over an interval is at an end or a control point).
    /// lo > hi (an empty interval) gives 0; a NaN bound (unknown) gives 1.
    double max_opacity(double lo, double hi) const;
    const std::vector<TransferPoint>& points() const { return points_; }
    /// First and last control values.
    double lo() const { return points_.front().value; }
    double hi() const { return points_.back().value; }

private:
    std::vector<TransferPoint> points_;
};

/// The preset names, in the order help texts list them.
std::vector<std::string_view> transfer_function_preset_names();
/// True when `name` is a preset.
bool is_transfer_function_preset(std::string_view name);
/// Preset `name` scaled to the value range [lo, hi] (see the header comment).
TransferFunction transfer_function_preset(std::string_view name, double lo, double hi);

}  // namespace meshless
