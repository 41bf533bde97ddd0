// NRRD reader (teem's "nearly raw raster data", versions NRRD0001..NRRD0005).
//
// Supports attached (.nrrd) and detached (.nhdr) headers; "data file:" as one file, "LIST"
// (names on the following lines) and the pattern form "fmt min max step [subdim]" (e.g.
// "quarter.%d 1 93 1"; one %d/%i/%u conversion with optional width/zero flag); encodings raw,
// gzip (gz) and ascii (text/txt); "endian", "byte skip" (-1 = data at end, raw only),
// "line skip", "spacings", "space directions" (spacing = length of each direction vector),
// "space origin". Dimension 3, or 2 (z = 1), or 4 whose extra axis has size 1.
// Units: world units of the header; voxels when none given.
// Throws IoError (cannot open header or data file), FormatError (bad magic, unsupported version,
// encoding or type, missing field, size mismatch, truncation). Thread-safety: reentrant.
// Dissertation: chapter 3 input volumes.
#pragma once
#include <string>

#include "formats/payload.hpp"

namespace meshless {

PayloadPlan plan_nrrd(const std::string& path);
VolumeInfo probe_nrrd(const std::string& path);
Volume read_nrrd(const std::string& path);

}  // namespace meshless
