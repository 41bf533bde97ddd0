// PNG input (libpng's simplified API): any PNG (grey, palette, RGB, with or without alpha, 1-16
// bits, interlaced) converted to 8-bit RGB, alpha composited onto black. Used by
// `meshless render --compare` (dissertation Figure 6.6 d/e: differences of renderings) and by tests.
// Checked sizes: width and height must lie in 1..16384 (kMaxPngSide), and the decoded size must be
// one the file's bytes can hold (deflate expands at most 1032:1: a header claiming more pixels than
// that is refused before anything is allocated for them).
// Throws: IoError naming the path when the file cannot be opened or read (or is a directory);
//         FormatError naming the path for anything that is not a valid PNG within those limits
//         (bad signature, damaged chunks, truncated data, sizes out of range).
// Thread-safety: reentrant (no shared state).
#pragma once
#include <span>
#include <string>

#include "kernels/splat_rasterizer.hpp"

namespace meshless {

inline constexpr int kMaxPngSide = 16384;

/// Reads the PNG file at `path`.
Image read_png(const std::string& path);
/// Decodes a PNG held in memory (`name` for messages).
Image decode_png(std::span<const unsigned char> bytes, const std::string& name);

}  // namespace meshless
