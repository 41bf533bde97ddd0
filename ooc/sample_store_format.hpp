// The sample store file (".mls", magic "\x89MLA\r\n\x1a\n"), version 2: paradigm (A) of the
// dissertation ("partial evaluation", section 3.5, Table 3.1) kept to what cannot be recomputed
// fast. For every non-constant finite cell of a brick store (.mlb), its cell row is filed under
// the span-space bucket of the cell's value interval (ooc/span_space_levels.hpp); the samples
// themselves (value, gradient, corners) are recomputed at extraction from the .mlb's bricks, for
// the candidate rows only. The .mls names its .mlb and records the .mlb's identity.
//
// Row key of a cell (i, j, k) of brick n (n = index in the .mlb's Morton-ordered table, (j, k) the
// cell's indices inside the brick, ny_b the brick's voxel count along y):
//     key = n * B^2 + j + (ny_b - 1) * k          (B = brick edge; key < brick count * B^2)
// so ascending keys visit bricks in Morton order and rows in paradigm (C)'s order. A bucket lists
// the distinct keys of its cells, ascending, gap coded (ooc/row_key_codec.hpp).
//
// Layout, all little endian:
//   header (512 bytes): magic[8] | u32 version (2) | u32 header bytes (512) | i64 dims[3] |
//       f64 origin[3] | f64 spacing[3] | u32 sample type | u32 brick edge B | f64 value_lo |
//       f64 value_hi | u32 levels L | u32 flags (bit 0: exact levels) | u64 key count |
//       u64 bucket count | u64 indexed cells | u64 constant cells | u64 non-finite cells |
//       u64 .mlb brick count | u64 .mlb file size | u32 .mlb header CRC | u32 .mlb index CRC |
//       u64 key bytes | zero padding to 256 | char .mlb path[252] (NUL padded; relative paths are
//       relative to the .mls's folder) | u32 CRC-32 of bytes [0, 508)
//   keys: key bytes, bucket after bucket in table order
//   bucket table: bucket count x 32 bytes: u16 a | u16 b | u32 CRC-32 of the bucket's key bytes |
//       u64 byte offset (from the start of the keys) | u64 byte length | u64 key count
//   footer (32 bytes): u64 table offset | u64 bucket count | u32 CRC-32 of the table | u32 version |
//       magic "MLAEND\0\0"
// Decoding checks, in order: magic, version, header CRC, header fields, exact file size, footer,
// table CRC, table consistency (order, contiguity, sums); sizes from the header are checked
// against the file size before anything is allocated. Bucket key bytes are checked (CRC, varint
// decoding, key bounds) when read.
// Errors: FormatError whose one-line message starts with the file name. Pure functions; thread-safe.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "formats/store_framing.hpp"
#include "kernels/grid.hpp"

namespace meshless {

inline constexpr std::uint32_t kSampleStoreVersion = 2;
inline constexpr std::size_t kSampleStoreHeaderBytes = 512;
inline constexpr std::size_t kSampleStoreBucketBytes = 32;
inline constexpr std::size_t kSampleStoreFooterBytes = kStoreFooterBytes;
inline constexpr std::size_t kSampleStorePathOffset = 256, kSampleStorePathBytes = 252;
inline constexpr char kSampleStoreMagic[8] = {'\x89', 'M', 'L', 'A', '\r', '\n', '\x1a', '\n'};
inline constexpr char kSampleStoreEndMagic[8] = {'M', 'L', 'A', 'E', 'N', 'D', '\0', '\0'};

/// Identity of the brick store a sample store was built from (checked when the .mls is opened).
struct BrickStoreIdentity {
    std::uint64_t file_bytes = 0;
    std::uint32_t header_crc = 0, index_crc = 0;  ///< the CRCs stored in the .mlb's header and footer
    std::uint64_t brick_count = 0;
    bool operator==(const BrickStoreIdentity&) const = default;
};

struct SampleStoreInfo {
    GridSpec grid;
    SampleType type = SampleType::u8;
    std::uint32_t brick_edge = 0;       ///< B of the .mlb
    double value_lo = 0, value_hi = 0;  ///< span-space level range (the .mlb's finite range)
    std::uint32_t levels = 1;
    bool exact_levels = false;
    std::uint64_t key_count = 0;        ///< stored (bucket, row) keys
    std::uint64_t bucket_count = 0;     ///< non-empty buckets
    std::uint64_t cells = 0;            ///< indexed cells (non-constant, finite corners)
    std::uint64_t constant_cells = 0, nonfinite_cells = 0;
    std::uint64_t key_bytes = 0;
    BrickStoreIdentity mlb;
    std::string mlb_path;               ///< as recorded (relative to the .mls's folder unless absolute)
};

/// One non-empty span-space bucket.
struct SampleBucket {
    std::uint16_t a = 0, b = 0;  ///< level(vmin), level(vmax)
    std::uint32_t crc = 0;
    std::uint64_t offset = 0, bytes = 0;  ///< key bytes, offset from the start of the keys
    std::uint64_t count = 0;              ///< keys
};

/// Header + table of a store, as decoded and validated.
struct SampleStoreLayout {
    SampleStoreInfo info;
    std::vector<SampleBucket> buckets;
    std::uint64_t key_limit() const;  ///< brick count * B^2
};

std::array<unsigned char, kSampleStoreHeaderBytes> encode_sample_store_header(const SampleStoreInfo& info);
void encode_sample_store_bucket(const SampleBucket& b, unsigned char* out);  ///< 32 bytes
std::array<unsigned char, kSampleStoreFooterBytes> encode_sample_store_footer(std::uint64_t table_offset,
                                                                              std::uint64_t bucket_count,
                                                                              std::uint32_t table_crc);
std::uint32_t sample_store_crc32(std::uint32_t crc, const void* data, std::size_t n);

/// Reads n bytes at an offset (the file or a buffer); throws FormatError/IoError naming `name`.
using ReadAt = std::function<void(void* dst, std::size_t n, std::uint64_t offset)>;
/// Decodes and validates header, footer and table of a store of `size` bytes (see above).
SampleStoreLayout decode_sample_store_layout(const ReadAt& read, std::uint64_t size, const std::string& name);

class RowSet;

/// Checks bucket i's bytes (CRC, varints, key bounds) and inserts its keys into `rows` (when not
/// null; its limit must be layout.key_limit()); FormatError naming `name` and the bucket.
void decode_sample_store_bucket(const SampleStoreLayout& layout, std::size_t i, const unsigned char* bytes,
                                RowSet* rows, const std::string& name);

/// The fuzz-friendly entry point: validates a whole store held in memory (layout and every
/// bucket) without its brick store; returns the layout or throws FormatError naming `name`.
SampleStoreLayout parse_sample_store_bytes(std::span<const unsigned char> bytes, const std::string& name);

}  // namespace meshless
