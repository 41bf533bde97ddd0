// PNG output of rendered images (dissertation section 3.6 figures): 8-bit RGB, no alpha, via
// libpng (SUB filter, zlib level 1: fast; the bytes depend only on the image). write_png goes through AtomicFile (temporary + rename; "-" = stdout),
// so a failed write never leaves a file that looks complete. read_png: formats/png_reader.hpp.
// Throws: IoError naming the path when the file cannot be created/written/opened;
//         InvalidArgument for an image whose size does not match its pixel buffer.
// Thread-safety: reentrant (no shared state).
#pragma once
#include <string>

#include "formats/atomic_file.hpp"
#include "formats/png_reader.hpp"  // read_png (callers of the former read_png here)
#include "kernels/splat_rasterizer.hpp"

namespace meshless {

void write_png(const Image& image, const std::string& path);
/// Encodes the image into `out` and flushes it (not committed: the caller commits, e.g. after its
/// other outputs);
/// errors name out.path(). BrokenPipe when out is stdout and its reader has gone.
void write_png(const Image& image, AtomicFile& out);

}  // namespace meshless
