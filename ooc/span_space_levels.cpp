#include "ooc/span_space_levels.hpp"

namespace meshless {

SpanSpaceLevels SpanSpaceLevels::make(SampleType t, double lo, double hi, std::uint32_t max_levels) {
    SpanSpaceLevels L;
    L.lo = lo;
    if (!(hi > lo)) return L;  // constant (or empty) volume: one level, no cells anyway
    if (t != SampleType::f32 && hi - lo + 1 <= static_cast<double>(max_levels)) {
        L.exact = true;
        L.count = static_cast<std::uint32_t>(hi - lo + 1);
        return L;
    }
    L.count = max_levels;
    L.scale = static_cast<double>(max_levels) / (hi - lo);
    return L;
}

SpanSpaceLevels SpanSpaceLevels::from_header(double lo, double hi, std::uint32_t count, bool exact) {
    SpanSpaceLevels L;
    L.lo = lo;
    L.count = count;
    L.exact = exact;
    L.scale = (exact || !(hi > lo)) ? 1.0 : static_cast<double>(count) / (hi - lo);
    return L;
}

bool SpanSpaceLevels::candidate(std::uint32_t a, std::uint32_t b, double thr) const {
    const std::uint32_t l = (*this)(thr);
    if (exact) {
        // integer corners: vmin < thr <= vmax with thr an integer in (lo, hi]
        if (!(thr > lo) || !(thr <= lo + static_cast<double>(count - 1))) return false;
        return a < l && l <= b;
    }
    return a <= l && l <= b;
}

}  // namespace meshless
