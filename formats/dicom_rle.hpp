// RLE Lossless pixel data (DICOM PS3.5 Annex G, transfer syntax 1.2.840.10008.1.2.5), checked and
// decoded here rather than by GDCM: GDCM's RLE decoder neither asserts nor fails on some damaged
// streams (two segments at one offset, a segment that decodes short) but fills the slice with
// whatever it reads, and it writes each run through an std::ostream (17 ms a 512 x 512 int16 slice
// against well under 1 ms here; bench/MEASURED.md).
// Checked: the encapsulated items (a Basic Offset Table item, then exactly one fragment: one frame),
// each inside the element; the fragment's 64-byte RLE header (segment count = bytes per sample x
// samples per pixel, 1..15; the first segment at byte 64; offsets strictly increasing and inside the
// fragment; unused offsets 0); and each segment's PackBits runs (G.3.1), which must give at least
// rows x columns bytes before the segment ends (bytes beyond are padding). Decoding: segment k holds
// byte k of every sample, most significant first (G.2); samples come out little endian.
// Throws FormatError "PATH: RLE pixel data at byte N: what" (N: the file offset). Pure; reentrant.
// Dissertation: none (input plumbing).
#pragma once
#include <cstdint>
#include <span>
#include <string>

namespace meshless {

/// Checks `element`, the bytes of an encapsulated Pixel Data element's value (its items, from the
/// first item tag to the sequence delimiter or the end), found at file offset `at` of `path`, for
/// one frame of `pixels` samples of `segments` bytes each (1: 8-bit, 2: 16-bit).
void check_rle_pixel_data(std::span<const unsigned char> element, std::uint64_t at, std::uint64_t pixels, int segments,
                          const std::string& path);
/// check_rle_pixel_data, then the frame decoded into `out` (pixels x segments bytes: 8-bit samples,
/// or 16-bit little endian).
void decode_rle_pixel_data(std::span<const unsigned char> element, std::uint64_t at, std::uint64_t pixels, int segments,
                           const std::string& path, std::byte* out);

}  // namespace meshless
