// VTK legacy reader: "# vtk DataFile Version x.y", DATASET STRUCTURED_POINTS, ASCII or BINARY.
//
// Keywords: DIMENSIONS, SPACING or ASPECT_RATIO, ORIGIN, POINT_DATA n, then the first point
// array: "SCALARS name type [1]" with an optional "LOOKUP_TABLE name" line, or the first
// single-component array of a "FIELD name k" block. BINARY data is big endian (VTK spec).
// Types: unsigned_char char unsigned_short short unsigned_int int unsigned_long long (8 bytes)
// float double vtktypeint64 vtktypeuint64.
// Throws IoError (cannot open), FormatError (wrong magic, other dataset types, bit/multi-component
// scalars, POINT_DATA count mismatch, truncated payload). Thread-safety: reentrant.
// Dissertation: chapter 3 input volumes.
#pragma once
#include <string>

#include "formats/payload.hpp"

namespace meshless {

PayloadPlan plan_vtk_legacy(const std::string& path);
VolumeInfo probe_vtk_legacy(const std::string& path);
Volume read_vtk_legacy(const std::string& path);

}  // namespace meshless
