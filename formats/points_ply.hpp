// Scattered points with a scalar from PLY (binary little/big endian and ASCII), dissertation
// chapters 4-5 inputs. Reads the vertex element (elements before it are skipped, list
// properties included); positions are x y z (any numeric type, kept in double precision).
// The scalar: options.value_name (FormatError listing the properties when absent), else a
// property named "value" or "scalar", else the first float/double property that is not x y z,
// a normal (nx ny nz) or "radius"; none -> positions only (has_values = false).
// formats/ply_points.hpp (PointRecord output, float precision) is left as it is.
// Throws FormatError (malformed header, list properties on vertices, truncated body), IoError.
// Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"

namespace meshless {

PointSet read_points_ply(const std::string& path, const PointSetOptions& options,
                         std::vector<std::string>* notes = nullptr);

}  // namespace meshless
