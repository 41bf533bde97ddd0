// Voreen/VolVis `.dat` sidecar: "ObjectFileName: x.raw", "Resolution: X Y Z",
// "SliceThickness: sx sy sz", "Format: UCHAR|CHAR|USHORT|SHORT|UINT|INT|FLOAT|DOUBLE".
// The payload is the raw file named by ObjectFileName (relative to the .dat), little endian
// unless "Endianness: big" is present, and must have exactly X*Y*Z*size bytes.
// Throws IoError (cannot open .dat or raw), FormatError (missing/bad keys, unknown Format,
// wrong raw size). Thread-safety: reentrant. Dissertation: input plumbing for chapter 3.
#pragma once
#include <string>

#include "formats/payload.hpp"

namespace meshless {

PayloadPlan plan_voreen_dat(const std::string& dat_path);
VolumeInfo probe_voreen_dat(const std::string& dat_path);
Volume read_voreen_dat(const std::string& dat_path);

}  // namespace meshless
