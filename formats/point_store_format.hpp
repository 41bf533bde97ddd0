// The point store file (".mlc", magic "\x89MLC\r\n\x1a\n"), version 1: scattered samples (x, y, z,
// value) in Morton order, cut into zstd-compressed bricks that are aligned octree cells, with a tail
// index of per-brick bounds, counts, value ranges and CRC-32s (docs/architecture.md "Brick store";
// the Morton on-disk order of dissertation section 3.6, applied to the scattered inputs of chapters
// 4-5). Written by ooc/point_store_writer.hpp, read by formats/point_store.hpp.
//
// Morton grid: level L (1..21) bits per axis over a cube of side s = the largest extent of the
// header bounds [lo, hi] (s = 0: every key is 0). A point p has the grid coordinates
//     q_a = min(2^L - 1, floor((p_a - lo_a) * (2^L / s)))      (point_store_key)
// and the key morton_encode(q) (kernels/morton.hpp). Points are stored by ascending (key, input
// order). A brick is the octree cell (level d, cell key c), i.e. the key range
// [c << 3(L-d), (c+1) << 3(L-d)), holding every point whose key falls in it; the bricks are the
// non-empty leaves of the octree that splits a cell while it holds more than B points (B = brick
// points). A cell of level L (one grid cell) with more than B points (duplicates) is cut into
// consecutive bricks of B points that share its key. So the key ranges of the index ascend and do
// not overlap (equal only for such level-L bricks).
//
// Layout, all little endian:
//   header (512 bytes): magic[8] | u32 version (1) | u32 header bytes (512) | u64 points |
//       u64 dropped non-finite (at conversion and by the readers) | u64 dropped blanked |
//       u64 brick count | f64 lo[3] | f64 hi[3] | f64 value min | f64 value max | u32 level L |
//       u32 brick points B | i32 zstd level | u32 flags (bit 0: has values) at 124 |
//       char value name[64] at 128 (NUL padded) | char source[256] at 192 (NUL padded: the input
//       files' names) | zero padding | u32 CRC-32 of bytes [0, 508)
//   bricks: one zstd frame each, contiguous from byte 512 in index order; a frame holds the
//       brick's points as count x 4 f64 (x, y, z, value)
//   index: brick count x 112-byte entries: u64 cell key | u32 cell level d | u32 CRC-32 of the
//       frame | u64 offset | u64 stored bytes | u64 count | u64 first point (points before it) |
//       f64 lo[3] | f64 hi[3] (exact bounds of its points) | f64 value min | f64 value max
//   footer (32 bytes): u64 index offset | u64 brick count | u32 CRC-32 of the index | u32 version |
//       magic "MLCEND\0\0"
// Decoding checks, in order: magic, version, header CRC, header fields (finite bounds lo <= hi
// with an extent of at most 1e150, finite value range, L, B), footer, exact file size, index CRC,
// every entry (level, key, contiguous offsets, 1 <= count <= B, prefix sums, finite bounds inside
// the header's, ascending disjoint key ranges), counts summing to the header's. Sizes from the
// header are checked against the file size before anything is allocated; a brick's allocation is
// at most B x 32 bytes (B <= 2^20) and made only after its frame was read and its CRC checked.
// Errors: FormatError, one line starting with the file name (and "brick N (cell level d key c,
// points [a,b))" for brick damage). Pure functions; thread-safe.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "formats/store_framing.hpp"

namespace meshless {

inline constexpr std::uint32_t kPointStoreVersion = 1;
inline constexpr std::size_t kPointStoreHeaderBytes = 512;
inline constexpr std::size_t kPointStoreEntryBytes = 112;
inline constexpr std::size_t kPointStoreFooterBytes = kStoreFooterBytes;
inline constexpr std::size_t kPointStoreRecordBytes = 32;  ///< x, y, z, value as f64
inline constexpr std::uint32_t kPointStoreMaxLevel = 21;
inline constexpr std::uint32_t kPointStoreMaxBrickPoints = 1u << 20;
inline constexpr double kPointStoreMaxExtent = 1e150;  ///< as the point-set readers (squared distances)
inline constexpr std::size_t kPointStoreValueNameBytes = 64, kPointStoreSourceBytes = 256;
inline constexpr char kPointStoreMagic[8] = {'\x89', 'M', 'L', 'C', '\r', '\n', '\x1a', '\n'};
inline constexpr char kPointStoreEndMagic[8] = {'M', 'L', 'C', 'E', 'N', 'D', '\0', '\0'};

struct PointStoreInfo {
    std::uint64_t points = 0;
    std::uint64_t dropped_nonfinite = 0, dropped_blanked = 0;
    std::uint64_t brick_count = 0;
    std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};  ///< bounds of all points
    double value_min = 0, value_max = 0;             ///< range of all values
    std::uint32_t level = kPointStoreMaxLevel;       ///< L, Morton bits per axis
    std::uint32_t brick_points = 4096;               ///< B
    std::int32_t zstd_level = 1;
    bool has_values = true;
    std::string value_name;  ///< at most 63 bytes
    std::string source;      ///< at most 255 bytes
};

struct PointBrickEntry {
    std::uint64_t key = 0;    ///< cell key at its level
    std::uint32_t level = 0;  ///< d, 0 (the whole cube) .. L
    std::uint32_t crc = 0;    ///< CRC-32 of the stored frame
    std::uint64_t offset = 0, stored_bytes = 0;
    std::uint64_t count = 0, first = 0;
    std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
    double vmin = 0, vmax = 0;
};

/// Morton keys of a store's grid (see above).
struct PointStoreGrid {
    std::array<double, 3> lo{0, 0, 0};
    double scale = 0;  ///< 2^L / s, 0 when s = 0
    std::uint32_t level = kPointStoreMaxLevel;
    PointStoreGrid() = default;
    PointStoreGrid(const std::array<double, 3>& lo, const std::array<double, 3>& hi, std::uint32_t level);
    std::uint64_t key(double x, double y, double z) const;
    /// First key of the cell (d, c) and one past its last.
    std::uint64_t cell_begin(std::uint32_t d, std::uint64_t c) const { return c << (3 * (level - d)); }
    std::uint64_t cell_end(std::uint32_t d, std::uint64_t c) const { return (c + 1) << (3 * (level - d)); }
};

/// Header + index of a store, as decoded and validated.
struct PointStoreLayout {
    PointStoreInfo info;
    std::vector<PointBrickEntry> bricks;
    std::uint64_t index_offset = 0;
    std::uint32_t header_crc = 0, index_crc = 0;
    PointStoreGrid grid() const { return PointStoreGrid(info.lo, info.hi, info.level); }
};

std::array<unsigned char, kPointStoreHeaderBytes> encode_point_store_header(const PointStoreInfo& info);
void encode_point_brick_entry(const PointBrickEntry& e, unsigned char* out);  ///< 112 bytes
std::array<unsigned char, kPointStoreFooterBytes> encode_point_store_footer(std::uint64_t index_offset,
                                                                            std::uint64_t brick_count,
                                                                            std::uint32_t index_crc);
std::uint32_t point_store_crc32(const void* data, std::size_t n);

/// Reads n bytes at an offset (the file or a buffer); throws FormatError/IoError naming the file.
using PointStoreReadAt = std::function<void(void* dst, std::size_t n, std::uint64_t offset)>;
/// Decodes and validates header, footer and index of a store of `size` bytes (see above).
PointStoreLayout decode_point_store_layout(const PointStoreReadAt& read, std::uint64_t size, const std::string& name);

/// "brick 17 (cell level 5 key 123, points [69632,73728))" for messages.
std::string point_brick_where(const PointStoreLayout& layout, std::size_t i);

/// Checks brick i's stored frame (CRC, content size) and decompresses it into out (count x 4
/// doubles: x, y, z, value), then checks every point: finite, inside the brick's bounds.
/// FormatError "NAME: brick ...: what" on any mismatch.
void decode_point_brick(const PointStoreLayout& layout, std::size_t i, std::span<const unsigned char> frame,
                        std::vector<double>& out, const std::string& name);

/// The full check of brick i's decoded points (verify): keys inside its cell and not decreasing,
/// bounds and value range exactly those of the points. Returns "" or what is wrong.
std::string check_point_brick(const PointStoreLayout& layout, std::size_t i, std::span<const double> points);

/// The fuzz-friendly entry point: validates a whole store held in memory (layout, then every
/// brick decoded and fully checked); returns the layout or throws FormatError naming `name`.
PointStoreLayout parse_point_store_bytes(std::span<const unsigned char> bytes, const std::string& name);

}  // namespace meshless
