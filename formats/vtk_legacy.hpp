// VTK legacy reader: "# vtk DataFile Version x.y", DATASET STRUCTURED_POINTS, ASCII or BINARY.
//
// Keywords: DIMENSIONS, SPACING or ASPECT_RATIO, ORIGIN, POINT_DATA n, then the point arrays:
// "SCALARS name type [1]" with an optional "LOOKUP_TABLE name" line, the arrays of a "FIELD name k"
// block ("name components tuples type"), VECTORS, NORMALS, TENSORS, TEXTURE_COORDINATES and
// COLOR_SCALARS (listed, never read: several components). Read: the array called `array`, else
// the first SCALARS or FIELD array. The values of the arrays before the one read are skipped
// (BINARY: their size; ASCII: their values, read through a 64 KiB window); `list_all` goes on to
// the end of the point data to list every array (PayloadPlan::arrays; a damaged tail after the
// array read ends the list). BINARY data is big endian (VTK spec).
// Types: unsigned_char char unsigned_short short unsigned_int int unsigned_long long (8 bytes)
// float double vtktypeint64 vtktypeuint64.
// Throws IoError (cannot open), FormatError (wrong magic, other dataset types, bit/multi-component
// scalars, no point array called `array` (formats/payload.hpp choose_volume_array), values that
// cannot be skipped, POINT_DATA count mismatch, truncated payload). Thread-safety: reentrant.
// Dissertation: chapter 3 input volumes.
#pragma once
#include <string>

#include "formats/payload.hpp"

namespace meshless {

PayloadPlan plan_vtk_legacy(const std::string& path, const std::string& array = "", bool list_all = false);
VolumeInfo probe_vtk_legacy(const std::string& path, const std::string& array = "", bool list_all = false);
Volume read_vtk_legacy(const std::string& path, const std::string& array = "");

}  // namespace meshless
