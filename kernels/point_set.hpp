// Scattered samples with one scalar each: what scattered and multiblock readers produce and what
// meshless fields are built from (dissertation chapters 4-5). A multiblock grid read as a point set
// keeps its blocks' names and dimensions (connectivity is dropped; blocks may overlap).
// Units: positions in the file's world units, values in the file's units.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

/// Axis-aligned bounds {lo, hi} of positions; {0,0,0},{0,0,0} when empty.
std::array<Vec3, 2> bounding_box(std::span<const Vec3> pos);

struct PointSetBlock {
    std::string name;                        ///< e.g. "grid 1", "multicomb_0.vts"
    std::array<std::int64_t, 3> dims{0, 0, 0};  ///< structured dims, or {count,1,1} for scattered data
    std::uint64_t first = 0, count = 0;      ///< range in PointSet::pos / value
};

struct PointSet {
    std::vector<Vec3> pos;
    std::vector<double> value;
    std::string value_name;                  ///< the scalar's name in the file ("density", "lum", ...)
    std::vector<PointSetBlock> blocks;       ///< at least one
    std::uint64_t dropped_nonfinite = 0;     ///< samples dropped by the reader (NaN/Inf coordinate or value)
    std::uint64_t dropped_blanked = 0;       ///< PLOT3D IBLANK == 0
    /// False for positions-only files (.npy (N,3), .pts, PLOT3D xyz without q): value is all 0.
    bool has_values = true;

    std::size_t size() const { return pos.size(); }
    /// Axis-aligned bounds of pos; {0,0,0},{0,0,0} when empty.
    std::array<Vec3, 2> bounds() const;
    /// [min, max] of value; {NaN, NaN} when empty.
    std::array<double, 2> value_range() const;
};

}  // namespace meshless
