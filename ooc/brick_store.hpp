// The brick store (.mlb): a regular volume cut into cubic bricks, each an independent zstd frame in
// the volume's native sample type with a one-voxel ghost layer, stored in Morton order with a tail
// index (docs/architecture.md "Brick store"; dissertation section 3.6, out-of-core iso-splatting in Morton
// order). Version 1 layout, all integers little endian:
//   header  (256 bytes): magic "\x89MLB\r\n\x1a\n" | u32 version | u32 header bytes (256) |
//           i64 dims[3] | f64 origin[3] | f64 spacing[3] | u32 sample type (SampleType) |
//           u32 brick edge B (cells) | u32 ghost (1) | i32 zstd level | f64 value min | f64 value max
//           | u64 brick count | i64 bricks per axis[3] | u32 patient axes given (1) or not (0, as every
//           store made before the axes were recorded: the bytes were padding) at byte 152 | f64 axes[3][3] at 160 (the
//           LPS unit direction of world +x, +y, +z, formats/anatomical_frame.hpp) | u32 length unit code
//           at byte 232 (formats/length_unit.hpp; 0, as in stores made before units were recorded: not
//           known) | the values' unit at 236, 16 bytes of text, NUL-padded where shorter (empty: not known) | zero padding |
//           u32 CRC-32 of bytes [0,252)
//   bricks  one zstd frame each, in ascending Morton key of the brick coordinates
//   index   brick count x 64-byte entries: u64 key | u64 offset | u64 stored bytes | u32 CRC-32 of
//           the stored frame | u32 coord[3] | f64 vmin | f64 vmax | u64 raw bytes (sorted by key)
//   footer  (32 bytes): u64 index offset | u64 brick count | u32 CRC-32 of the index | u32 version |
//           magic "MLBEND\0\0"
// Brick (bx,by,bz) holds the voxels [b*B, min(b*B + B + 1, n)) on each axis (B cells plus the
// ghost layer), so it owns exactly the cells [b*B, min(b*B + B, n-1)): every cell of the volume
// belongs to exactly one brick, and a brick is a complete little volume (a VolumeView).
// Bricks per axis: max(1, ceil((n-1)/B)) (an axis of one sample has one brick of one voxel).
// Frames are contiguous: the first starts at byte 256, each next one where the previous ends, the
// index right after the last. Header value range: over all finite samples ({0,0} when none, as
// Volume::value_range); vmin/vmax: range of the brick's finite samples (ghost layer included),
// NaN when it has none.
// Errors: FormatError naming the file and what is wrong ("not a brick store (wrong magic)",
// "unsupported brick store version 2", "truncated or unfinished brick store", "header/index
// checksum mismatch", and for brick damage "PATH: brick 17 (voxels [32,65)x[0,33)x[0,10)):
// checksum mismatch"); IoError when the file cannot be opened or read.
// Thread-safety: a BrickStore is immutable after open(); read_brick may be called concurrently.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "formats/store_framing.hpp"
#include "kernels/grid.hpp"

namespace meshless {

inline constexpr std::uint32_t kBrickStoreVersion = 1;

struct BrickStoreInfo {
    GridSpec grid;
    SampleType type = SampleType::u8;
    std::uint32_t brick_edge = 32;  ///< B, cells per brick edge
    std::uint32_t ghost = 1;
    std::int32_t zstd_level = 1;
    double value_min = 0, value_max = 0;  ///< over all finite samples
    std::array<std::int64_t, 3> bricks_per_axis{0, 0, 0};
    std::uint64_t brick_count = 0;
    /// What the converted volume's header said about the patient's axes (the LPS unit direction of
    /// world +x, +y, +z), so that pictures of the store face as pictures of the volume do.
    std::optional<std::array<std::array<double, 3>, 3>> patient_axes;
    /// The converted volume's length unit where its file said it (formats/length_unit.hpp), else "".
    std::string length_unit;
    /// The values' unit where the converted volume's file said it (formats/length_unit.hpp
    /// value_unit_text: at most 16 bytes, printable), else "".
    std::string value_unit;
};

struct BrickEntry {
    std::uint64_t key = 0;       ///< morton_encode(coord)
    std::uint64_t offset = 0;    ///< byte offset of the zstd frame in the file
    std::uint64_t stored_bytes = 0;
    std::uint32_t crc = 0;       ///< CRC-32 of the stored frame
    std::array<std::uint32_t, 3> coord{0, 0, 0};
    double vmin = 0, vmax = 0;
    std::uint64_t raw_bytes = 0; ///< decompressed bytes = voxel count of the brick * sample size
};

/// Voxel box of the brick at `coord`: first voxel and voxel counts (<= B+1 each).
struct BrickBox {
    std::array<std::int64_t, 3> first{0, 0, 0};
    std::array<std::int64_t, 3> dims{0, 0, 0};
    std::int64_t voxel_count() const { return dims[0] * dims[1] * dims[2]; }
};

/// Read access to a brick store. Opening validates header, footer and index (not the bricks).
/// read_brick is thread-safe (positional reads on a shared descriptor).
class BrickStore {
public:
    static std::unique_ptr<BrickStore> open(const std::string& path);
    ~BrickStore();
    const std::string& path() const { return path_; }
    const BrickStoreInfo& info() const { return info_; }
    /// Sorted by key (Morton order), which is also the file order.
    const std::vector<BrickEntry>& bricks() const { return bricks_; }
    /// The grid of brick i's voxels: dims (<= B+1 each), origin = world position of its first voxel.
    GridSpec brick_grid(std::size_t i) const;
    /// Index of brick i's first voxel in the whole volume.
    std::array<std::int64_t, 3> brick_first_voxel(std::size_t i) const;
    /// Largest raw_bytes over all bricks (the minimum useful cache budget).
    std::uint64_t max_brick_bytes() const;
    /// Decompresses brick i into out (resized), checking CRC and size; FormatError names the brick
    /// index and its voxel range on any mismatch.
    void read_brick(std::size_t i, std::vector<std::byte>& out) const;
    /// Voxel box of brick i.
    BrickBox box(std::size_t i) const;

private:
    BrickStore();
    std::string path_;
    int fd_ = -1;
    BrickStoreInfo info_;
    std::vector<BrickEntry> bricks_;
    struct ContextPool;                   ///< reusable zstd decompression contexts (mutex-guarded)
    std::unique_ptr<ContextPool> pool_;
};

/// True when the file starts with the brick store magic (false for a missing or short file).
bool is_brick_store(const std::string& path);

// ---- Layout helpers shared by the writer (brick_converter.cpp), the reader and the tests that
// ---- craft damaged stores. Pure functions.
inline constexpr std::size_t kBrickStoreHeaderBytes = 256;
inline constexpr std::size_t kBrickIndexEntryBytes = 64;
inline constexpr std::size_t kBrickStoreFooterBytes = kStoreFooterBytes;
inline constexpr char kBrickStoreMagic[8] = {'\x89', 'M', 'L', 'B', '\r', '\n', '\x1a', '\n'};
inline constexpr char kBrickStoreEndMagic[8] = {'M', 'L', 'B', 'E', 'N', 'D', '\0', '\0'};

/// Bricks per axis: max(1, ceil((n-1)/B)) (a 1-sample axis still has one brick).
std::array<std::int64_t, 3> brick_store_bricks_per_axis(const std::array<std::int64_t, 3>& dims, std::uint32_t edge);
/// Voxel box of the brick at `coord`.
BrickBox brick_store_box(const std::array<std::int64_t, 3>& volume_dims, std::uint32_t edge,
                         const std::array<std::uint32_t, 3>& coord);
/// "[32,65)x[0,33)x[0,10)" for messages.
std::string voxel_range_string(const BrickBox& b);
/// CRC-32 (zlib polynomial) of n bytes.
std::uint32_t brick_store_crc32(const void* data, std::size_t n);
/// The 256-byte header (CRC included).
std::vector<std::byte> encode_brick_store_header(const BrickStoreInfo& info);
/// One 64-byte index entry into out[0..64).
void encode_brick_index_entry(const BrickEntry& e, std::byte* out);
/// The 32-byte footer.
std::vector<std::byte> encode_brick_store_footer(std::uint64_t index_offset, std::uint64_t brick_count,
                                                 std::uint32_t index_crc);

}  // namespace meshless
