// The fitted-field file (".mlf", magic "\x89MLF\r\n\x1a\n"), version 1: a meshless field
// (rbf-grid, dissertation section 4.3; mpu, section 5.5; global-rbf, section 2.1.1) fitted once by
// `meshless fit` and loaded by every command that takes --field, evaluating bit-identically to the
// field built from the same points with the same options. It records the identity of the points it
// was fitted to (kernels/point_set_identity.hpp), so a command that also has the data refuses a
// .mlf fitted to other data.
//
// Layout, all little endian:
//   header (64 bytes): magic[8] | u32 version (1) | u32 header bytes (64) | u32 field kind (0 rbf-grid,
//       1 mpu, 2 global-rbf) | u32 section count | u64 file bytes | zero padding to 60 |
//       u32 CRC-32 of bytes [0, 60)
//   sections, one after another to the end of the file, each:
//       section header (48 bytes): char name[16] (a-z, 0-9, _; NUL padded) | u32 element type
//           (0 bytes, 1 f64, 2 i64, 3 u32, 4 i32) | u32 flags (bit 0: the payload is one zstd frame;
//           bit 1: its elements were byte-shuffled before compression, byte plane after byte plane) |
//           u64 element count | u64 stored payload bytes | u32 CRC-32 of the stored payload |
//           u32 CRC-32 of bytes [0, 44) of this section header
//       payload: the elements (count x element size bytes) or their zstd frame
//   The first three sections are "params" (80 bytes: u32 kind, support (0 27 neighbours, 1 paper
//   radius), rbf_grid_max_local, rbf_grid_min_local, mpu_max_points, mpu_min_points, mpu_max_depth,
//   global_max_points, normalise_axes, rbf_grid_local_points (K; 0 = all points, what files written
//   before K existed hold there, and what they were fitted with) | f64 hardy_c_rel, hardy_c_world, binning_m, mpu_alpha,
//   merge_rel), "identity" (u64 count | f64 lo[3] | f64 hi[3] | f64 value min, max | u64 hash |
//   u64 dropped non-finite | u64 dropped blanked | u32 has values | u32 name bytes (<= 1024) | name)
//   and "build_stats" (168 bytes, FieldBuildStats without the time: u64 input_points, merged_points,
//   used_points, locals, interpolated, rank_deficient, regularised, linear_fallback,
//   polynomial_only, capped, grown, max_local_points, octree_nodes, memory_bytes | i64 grid_dims[3] |
//   u32 octree_depth, 0 | f64 merge_tolerance, hardy_c_world, mean_local_points); then the field's
//   state arrays (kernels/field_state.hpp) in the order the field writes them. The file holds no
//   time or path, so fitting the same points with the same options gives the same bytes, for any
//   thread count.
// Decoding checks, in order: magic, version ("made by a newer/older version"), header CRC, header
// fields, the exact file size (truncated or appended bytes), then per section: its header fits,
// header CRC, name, type, flags, sizes against the bytes left in the file (nothing is allocated
// before the file proves it holds the payload; a zstd payload grows its output as it decodes,
// capped at the declared size), payload CRC; then the metadata, and the field's state is validated
// (kernels/field_state.hpp: sizes, every index in range, derived scalars).
// Errors: FormatError "PATH: offset N: what", one line; IoError when the file cannot be read or
// written. Writing is atomic (formats/atomic_file.hpp): a temporary beside the target, renamed.
// Thread-safety: reentrant functions.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_set_identity.hpp"

namespace meshless {

inline constexpr std::uint32_t kFieldFileVersion = 1;
inline constexpr std::size_t kFieldFileHeaderBytes = 64;
inline constexpr std::size_t kFieldFileSectionHeaderBytes = 48;
inline constexpr char kFieldFileMagic[8] = {'\x89', 'M', 'L', 'F', '\r', '\n', '\x1a', '\n'};

/// What the points a field was fitted to were (beyond their identity), for `meshless info`.
struct FittedData {
    PointSetIdentity identity;
    std::uint64_t dropped_nonfinite = 0, dropped_blanked = 0;  ///< by the reader
    bool has_values = true;
    std::string value_name;  ///< at most 1024 bytes kept
};

struct FieldFileSection {
    std::string name;
    std::uint32_t type = 0;          ///< element type code (see above)
    std::uint64_t offset = 0;        ///< of its section header
    std::uint64_t count = 0;         ///< elements
    std::uint64_t raw_bytes = 0;     ///< count x element size
    std::uint64_t stored_bytes = 0;  ///< payload in the file
    bool compressed = false, shuffled = false;
    std::uint32_t stored_crc = 0;    ///< CRC-32 of the stored payload
};

struct FieldFileInfo {
    std::uint32_t version = kFieldFileVersion;
    FieldParams params;              ///< params.kind is the field's kind
    FittedData data;
    FieldBuildStats stats;           ///< build_seconds is 0 (not stored)
    std::uint64_t file_bytes = 0;
    std::vector<FieldFileSection> sections;
};

struct FieldFile {
    FieldFileInfo info;
    std::unique_ptr<Field> field;
};

/// Writes `field` (made by make_field() with `params` from the points described by `data`) to
/// `path` atomically. zstd_level 0 stores every array raw; otherwise each array is compressed
/// (byte-shuffled) unless that saves less than 3%. Throws IoError; InvalidArgument when the path is
/// not a regular file ("-", a device, a FIFO) or the field has no saved form.
void write_field_file(const std::string& path, const Field& field, const FieldParams& params, const FittedData& data,
                      const FieldBuildStats& stats, int zstd_level = 1);

/// Reads and validates a .mlf and builds its field (see the checks above).
FieldFile read_field_file(const std::string& path);

/// The same from bytes in memory (tests, the fuzz target); `name` starts the messages.
FieldFile parse_field_file_bytes(std::span<const unsigned char> bytes, const std::string& name);

/// True when the file starts with the .mlf magic (false for a missing or short file).
bool is_field_file(const std::string& path);

/// FormatError "PATH was fitted to other data: its N points, hash H, ...; these are M points, hash K, ..."
/// unless `data` is the data the file was fitted to.
void check_fitted_to(const FieldFileInfo& info, const PointSetIdentity& data, const std::string& path);

}  // namespace meshless
