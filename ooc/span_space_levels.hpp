// Span space of the paradigm-(A) sample store (dissertation section 3.5: out-of-core active-cell
// lookup; Livnat, Shen & Johnson's span space). A cell with corner interval [vmin, vmax] is the
// point (vmin, vmax) of span space; quantising both axes into L levels cuts span space into
// triangular buckets (a, b), a = level(vmin) <= b = level(vmax). A cell can be active for an
// isovalue only when its bucket satisfies a <= level(thr) <= b (level is monotone), so a query
// visits exactly those buckets.
//
// Levels: level(v) = clamp(floor((v - lo) * scale), 0, L-1). Integer volumes whose value range has
// at most `max_levels` distinct values get exact levels (scale 1, L = hi - lo + 1: one level per
// grey value); then a bucket with a < level(thr) <= b holds only active cells (vmin < thr <= vmax)
// and one with a == level(thr) none. Otherwise scale = L / (hi - lo) and the buckets touching
// level(thr) also hold inactive cells (the reader's exact test sorts them out).
// Bucket order (the store's table and file order): a ascending, then b ascending; for a query the
// candidate buckets of each row a are a suffix of that row.
// Pure value type; thread-safe.
#pragma once
#include <cstddef>
#include <cstdint>

#include "kernels/grid.hpp"

namespace meshless {

inline constexpr std::uint32_t kMaxSpanSpaceLevels = 1024;

struct SpanSpaceLevels {
    double lo = 0, scale = 1;
    std::uint32_t count = 1;  ///< L
    bool exact = false;

    /// The levels of a volume of type t whose finite values lie in [lo, hi]; max_levels in
    /// 1..kMaxSpanSpaceLevels (checked by the writer).
    static SpanSpaceLevels make(SampleType t, double lo, double hi, std::uint32_t max_levels);
    /// The levels recorded in a store header (scale derived as make() does).
    static SpanSpaceLevels from_header(double lo, double hi, std::uint32_t count, bool exact);

    std::uint32_t operator()(double v) const {
        const double x = (v - lo) * scale;
        if (!(x > 0)) return 0;
        if (x >= static_cast<double>(count - 1)) return count - 1;
        return static_cast<std::uint32_t>(x);
    }
    /// Dense index of bucket (a, b), a <= b < L, in table order.
    std::size_t bucket(std::uint32_t a, std::uint32_t b) const {
        const std::size_t L = count;
        return static_cast<std::size_t>(a) * L - static_cast<std::size_t>(a) * (a - 1) / 2 + (b - a);
    }
    std::size_t buckets() const { return static_cast<std::size_t>(count) * (count + 1) / 2; }
    /// Whether bucket (a, b) may hold a cell active at threshold thr (see kernels/
    /// kernels/iso_threshold.hpp active_threshold): a <= level(thr) <= b, and with exact levels
    /// a < level(thr) and thr inside (lo, lo + L - 1].
    bool candidate(std::uint32_t a, std::uint32_t b, double thr) const;
};

}  // namespace meshless
