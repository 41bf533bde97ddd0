// VTK XML ImageData (.vti) reader, single piece.
//
// Reads the point array called `array` when given, else the one named by <PointData Scalars="...">
// (else the first point DataArray), one component; probe_vti lists every point DataArray
// (VolumeInfo::arrays). Data formats: ascii, binary (inline base64) and appended (raw or base64);
// compressor vtkZLibDataCompressor or none; header_type UInt32 (default) or UInt64;
// byte_order LittleEndian or BigEndian (applies to headers and data). Compressed layout: header
// [nblocks, blocksize, last_blocksize, csize_0..csize_{n-1}], then the zlib blocks.
// Types Int8..UInt64, Float32, Float64 (see volume_reader.hpp for conversions).
// Grid: dims from the Piece (else Whole) extent, origin = Origin + extent_min * Spacing;
// a non-identity Direction is ignored.
// Throws IoError (cannot open), FormatError (not ImageData, unsupported compressor, several
// pieces, no point array called `array` (formats/payload.hpp choose_volume_array), multi-component, size mismatch, corrupt base64/zlib). Thread-safety: reentrant.
// Dissertation: chapter 3 input volumes.
#pragma once
#include <string>

#include "formats/volume_reader.hpp"

namespace meshless {

VolumeInfo probe_vti(const std::string& path, const std::string& array = "");
Volume read_vti(const std::string& path, const std::string& array = "");
/// read_vti's checks and decoding without keeping the samples (meshless info): compressed blocks
/// inflated one at a time. Throws as read_vti.
void prove_vti(const std::string& path, const std::string& array = "");

}  // namespace meshless
