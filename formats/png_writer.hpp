// PNG output of rendered images (dissertation section 3.6 figures): 8-bit RGB, no alpha, rows
// unfiltered (filter type None), one zlib stream deflated by libdeflate at level 2 in IDAT chunks
// of 1 MiB, CRC-32 by libdeflate (formats/crc32.hpp): 40 % less time than libpng + zlib level 1 on
// rendered pictures, at a similar or smaller size; the bytes depend only on the image. libpng
// reads them back (formats/png_reader.hpp, the tests). write_png goes through AtomicFile
// (temporary + rename; "-" = stdout), so a failed write never leaves a file that looks complete.
// Memory: the image's bytes again (the scanlines), plus the compressed stream (its buffer is sized
// for the worst case but touched only as far as the stream reaches) and the output's 1 MiB buffer.
// Throws: IoError naming the path when the file cannot be created/written/opened;
//         InvalidArgument for an image whose size does not match its pixel buffer;
//         std::bad_alloc when memory runs out.
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
