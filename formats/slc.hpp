// SLC reader (VolVis "slice" format, as read by VTK's vtkSLCReader).
//
// Layout: ASCII header "11111" (magic), "X Y Z bits", "sx sy sz", "units origin modification
// compression", then the icon "W H X" followed by 3*W*H bytes (RGB planes), then per z slice
// "N X" and N bytes: RLE when compression = 1 (byte c: run = c & 0x7f, 0 ends; high bit set ->
// copy `run` literal bytes, else repeat the next byte `run` times), raw when 0.
// Only 8-bit voxels. A slice that decodes short by at most one row is padded with zeros (VTK's
// embryo.slc decodes every slice one byte short); a larger shortfall (more than a row or half a
// plane) or an overflow is an error. Sizes are checked (kernels/checked_size.hpp) and a header
// claiming more voxels than the slice bytes can decode to is refused before anything is allocated.
// Throws IoError (cannot open), FormatError (wrong magic, bad header, truncated or corrupt RLE).
// Thread-safety: reentrant. Dissertation: chapter 3 input volumes.
#pragma once
#include <string>

#include "formats/volume_reader.hpp"

namespace meshless {

/// The header, the icon's size and the claimed voxels against the file's size (read_slc's checks
/// before it allocates, with its messages); reads the first 4 KiB.
VolumeInfo probe_slc(const std::string& path);
Volume read_slc(const std::string& path);
/// read_slc's checks and slice decoding into one reused plane (meshless info). Throws as read_slc.
void prove_slc(const std::string& path);

}  // namespace meshless
