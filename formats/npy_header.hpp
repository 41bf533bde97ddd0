// The header of a NumPy .npy file (format versions 1.0, 2.0 and 3.0): magic "\x93NUMPY", version,
// header length (uint16 little endian for 1.0, uint32 for 2.0/3.0), then a Python dict literal with
// 'descr' (the dtype), 'fortran_order' (True/False) and 'shape' (a tuple of non-negative ints).
// The array's bytes follow the header (data_offset), C order (last index fastest) or Fortran order
// (first index fastest).
// dtypes: the numeric ones the readers take, '<' '>' '|' or '=' byte order: u1 i1 u2 i2 u4 i4 u8 i8
// f4 f8 (and b1/bool as u1). Object arrays ('O'), structured dtypes (a list), strings, complex
// and float16 are refused with the dtype named.
// Units: bytes. Throws FormatError naming the path (bad magic, unknown version, a header longer
// than the file, a malformed dict, an unsupported dtype, a shape entry that is not a
// non-negative integer, more than 32 dimensions). Thread-safety: reentrant.
// Dissertation: input plumbing (chapter 3 volumes, chapters 4-5 point sets).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "formats/stored_type.hpp"

namespace meshless {

struct NpyHeader {
    StoredType type = StoredType::f32;
    bool big_endian = false;
    bool fortran_order = false;
    std::vector<std::int64_t> shape;  ///< as the file lists it (C order: slowest first)
    std::uint64_t data_offset = 0;    ///< bytes before the array's first byte
    std::string descr;                ///< the dtype as written, e.g. "<f4" (for messages)
};

/// Parses the header at the start of `bytes` (the whole file or a prefix holding the header).
NpyHeader parse_npy_header(std::string_view bytes, const std::string& path);

/// Reads and parses the header of the file at `path` (at most its first 1 MiB + 12 bytes are read).
/// IoError when it cannot be opened.
NpyHeader read_npy_header(const std::string& path);

/// The number of dimensions of the .npy at `path`, or -1 when it is not a readable .npy (never throws):
/// the dispatch between 3-D volumes (formats/npy_volume.hpp) and 2-D point sets (formats/points_raw.hpp).
int npy_ndim(const std::string& path);

/// "(64, 32, 16)" for messages.
std::string npy_shape_text(const std::vector<std::int64_t>& shape);

}  // namespace meshless
