// The structure of RLE Lossless pixel data (DICOM PS3.5 Annex G, transfer syntax
// 1.2.840.10008.1.2.5) checked before GDCM decodes it: GDCM's RLE decoder neither asserts nor fails on
// some damaged streams (two segments at one offset, a segment that decodes short) but fills the
// slice with whatever it reads, so a damaged file would give a wrong volume without a word.
// Checked: the encapsulated items (a Basic Offset Table item, then exactly one fragment: one frame),
// each inside the element; the fragment's 64-byte RLE header (segment count = bytes per sample x
// samples per pixel, 1..15; the first segment at byte 64; offsets strictly increasing and inside the
// fragment; unused offsets 0); and each segment's PackBits runs (G.3.1), which must give at least
// rows x columns bytes before the segment ends (bytes beyond are padding). Nothing is decoded.
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

}  // namespace meshless
