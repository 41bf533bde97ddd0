// NRRD writer (attached header, raw encoding, little endian): regular volumes out, e.g. a scattered
// field resampled to a grid (meshless resample), readable by meshless, ParaView, 3D Slicer, teem.
// Grid placement as "space dimension: 3", "space directions" (diagonal: the spacing) and
// "space origin". Written through AtomicFile (temporary + rename; "-" = stdout). Throws IoError.
#pragma once
#include <string>

#include "kernels/grid.hpp"

namespace meshless {

void write_nrrd(const Volume& v, const std::string& path, const std::string& comment = "");

/// The attached header write_nrrd writes (ends with the blank line); the raw samples follow it
/// (x fastest, little endian). For writers that stream the samples (stream/field_sinks.hpp).
std::string nrrd_header(const GridSpec& g, SampleType type, const std::string& comment = "");

}  // namespace meshless
