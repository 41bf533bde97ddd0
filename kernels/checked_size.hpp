// Checked size arithmetic: the one helper every reader (and GridSpec) uses for sizes that come from
// a file's header (dims, extents, strides, payload sizes, record counts).
//
// Each function computes an unsigned 64-bit (or signed, for extents) result and throws FormatError
// when it does not fit; the message starts with the caller's `context` (conventionally
// "PATH: FIELD", e.g. "a.nrrd: sizes"), so the user sees which file and field is at fault.
// kMaxPayloadBytes caps a single in-memory payload (2^56 bytes = 64 PiB: far beyond any machine,
// far below any overflow in the byte arithmetic that follows; element counts below it times a
// sample size of at most 8 stay far from 2^63). Conventions: docs/development.md "Hostile input".
// Thread-safety: pure functions. Dissertation: none (input plumbing).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

#include "kernels/errors.hpp"

namespace meshless {

/// Largest byte count (and element count) a header may claim for one payload.
inline constexpr std::uint64_t kMaxPayloadBytes = std::uint64_t{1} << 56;

/// Throws FormatError("CONTEXT: WHAT"); out of line so the checked paths stay small.
[[noreturn]] void throw_size_error(std::string_view context, const std::string& what);

/// a * b, or FormatError "CONTEXT: a x b overflows" when it exceeds kMaxPayloadBytes.
inline std::uint64_t checked_mul(std::uint64_t a, std::uint64_t b, std::string_view context) {
    std::uint64_t r;
    if (__builtin_mul_overflow(a, b, &r) || r > kMaxPayloadBytes)
        throw_size_error(context, std::to_string(a) + " x " + std::to_string(b) + " is too large (size overflow)");
    return r;
}

/// a + b, or FormatError when it exceeds kMaxPayloadBytes.
inline std::uint64_t checked_add(std::uint64_t a, std::uint64_t b, std::string_view context) {
    std::uint64_t r;
    if (__builtin_add_overflow(a, b, &r) || r > kMaxPayloadBytes)
        throw_size_error(context, std::to_string(a) + " + " + std::to_string(b) + " is too large (size overflow)");
    return r;
}

/// A signed count from a header converted to unsigned: FormatError when negative or above
/// kMaxPayloadBytes.
inline std::uint64_t checked_count(std::int64_t v, std::string_view context) {
    if (v < 0 || static_cast<std::uint64_t>(v) > kMaxPayloadBytes)
        throw_size_error(context, std::to_string(v) + " is out of range (0.." + std::to_string(kMaxPayloadBytes) + ")");
    return static_cast<std::uint64_t>(v);
}

/// The number of samples hi - lo + 1 of an inclusive extent [lo, hi] (VTK's Extent, WholeExtent):
/// FormatError when hi < lo or the difference overflows.
inline std::int64_t checked_extent(std::int64_t lo, std::int64_t hi, std::string_view context) {
    std::int64_t d;
    if (__builtin_sub_overflow(hi, lo, &d) || d < 0 || static_cast<std::uint64_t>(d) >= kMaxPayloadBytes)
        throw_size_error(context, std::to_string(lo) + ".." + std::to_string(hi) + " is not a valid extent");
    return d + 1;
}

/// dims[0] * dims[1] * dims[2] for dims that must each be >= 1.
inline std::uint64_t checked_volume(std::int64_t d0, std::int64_t d1, std::int64_t d2, std::string_view context) {
    if (d0 < 1 || d1 < 1 || d2 < 1)
        throw_size_error(context, std::to_string(d0) + "x" + std::to_string(d1) + "x" + std::to_string(d2) +
                                      ": every size must be >= 1");
    return checked_mul(checked_mul(static_cast<std::uint64_t>(d0), static_cast<std::uint64_t>(d1), context),
                       static_cast<std::uint64_t>(d2), context);
}

}  // namespace meshless
