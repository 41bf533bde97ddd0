// The identity of a point set a meshless field was fitted to: point count, bounds, value range and
// a 64-bit hash over every position and value as doubles, in order. A fitted field saved to a file
// (formats/field_file.hpp, ".mlf") records it, and commands that are given both the data and a
// .mlf compare it with the data's before using the field (dissertation chapter 4: the isosurface
// of overlapping blocks is projected onto the field built from exactly their nodes).
//
// The hash (format-defining; changing it changes the .mlf format): over the 64-bit patterns w of
// x, y, z, value of point 0, then of point 1, ..., with m(w) the SplitMix64 finaliser
// (z ^= z >> 30; z *= 0xBF58476D1CE4E5B9; z ^= z >> 27; z *= 0x94D049BB133111EB; z ^= z >> 31):
//     h = 0x9E3779B97F4A7C15 ^ count;   h = (h ^ m(w + 0x9E3779B97F4A7C15)) * 0x100000001B3 for every w;
//     hash = m(h).
// So a different order, a changed bit of any coordinate or value (0.0 vs -0.0 included) or another
// count gives another identity. Points with NaN coordinates never reach a field (readers drop them).
// Units: the data's. Thread-safety: pure function. Throws nothing.
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "kernels/point_set.hpp"

namespace meshless {

struct PointSetIdentity {
    std::uint64_t count = 0;
    std::array<Vec3, 2> bounds{};        ///< {lo, hi}; zeros when empty
    std::array<double, 2> value_range{};  ///< {min, max}; zeros when empty
    std::uint64_t hash = 0;

    /// Same data: count, hash and the bit patterns of bounds and value range agree.
    bool same_data(const PointSetIdentity& o) const;
};

PointSetIdentity point_set_identity(const PointSet& points);

/// "47025 points, hash 0123456789abcdef, bounds (x,y,z)..(x,y,z)" for messages.
std::string describe_identity(const PointSetIdentity& id);

}  // namespace meshless
