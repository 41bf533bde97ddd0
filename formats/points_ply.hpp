// Scattered points with a scalar from PLY (binary little/big endian and ASCII), dissertation
// chapters 4-5 inputs: a thin wrapper of the PLY codec (formats/ply.hpp) for PointSet.
// Reads the vertex element (elements before and after it are read past and checked); positions are
// x y z (any numeric type, kept in double precision). The scalar: options.value_name
// (FormatError listing the properties when absent), else a property named "value" or "scalar",
// else the first float/double property that is not x y z, a normal (nx ny nz) or "radius";
// none -> positions only (has_values = false). NaN/Inf samples follow PointSetBuilder's policy
// (dropped and counted, or refused with options.strict). Bytes after the last element are refused
// unless options.allow_trailing (then noted).
// Throws FormatError (the codec's defects, list properties on vertices, missing x y z), IoError.
// Thread-safety: reentrant.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"

namespace meshless {

PointSet read_points_ply(const std::string& path, const PointSetOptions& options,
                         std::vector<std::string>* notes = nullptr);

/// The same vertices streamed (memory: the reader's buffer and one chunk of 65536 records, whatever
/// the file's size): begin(value name, has values) once, then chunk(x, y, z, value, x, ...) for
/// the finite points in file order; NaN/Inf records are counted in dropped_nonfinite (refused
/// with options.strict). No minimum count. Throws as read_points_ply.
using PlyPointsBegin = std::function<void(const std::string& value_name, bool has_values)>;
using PlyPointsChunk = std::function<void(std::span<const double> xyzv)>;
void stream_points_ply(const std::string& path, const PointSetOptions& options, const PlyPointsBegin& begin,
                       const PlyPointsChunk& chunk, std::uint64_t& dropped_nonfinite,
                       std::vector<std::string>* notes = nullptr);

}  // namespace meshless
