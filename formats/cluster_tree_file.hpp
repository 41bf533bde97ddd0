// The cluster-binary-tree file (".mlh", magic "\x89MLH\r\n\x1a\n"), version 4: the hierarchy of
// dissertation chapter 6 (kernels/cluster_tree.hpp) built once by `meshless hierarchy` and read by
// `meshless lod`, `meshless info` and every command that reads a point set (a level of detail of
// it, formats/point_set_reader.hpp).
//
// Layout, all little endian:
//   header (64 bytes): magic[8] | u32 version (1..4) | u32 header bytes (64) | u64 file bytes |
//       u64 meta bytes (M) | u64 node count (N) | zero padding to 60 | u32 CRC-32 of bytes [0, 60)
//   meta (M bytes, at 64): u64 samples | u64 dropped non-finite | u64 splits | u64 skipped splits |
//       u32 depth | u32 neighbours (k) | u32 min cluster | u32 PCA scaling (0 raw, 1 normalised) |
//       u64 max splits | f64 max error | f64 hardy_c_rel | f64 hardy_c_world (requested, 0 = relative) |
//       f64 Hardy's c used (world) | f64 error reached | f64 bounds lo[3], hi[3] | f64 value min, max |
//       u32 split order (0 max error, 1 weighted) | u32 cluster value (0 fit, 1 mean) | f64 size term |
//       u32 name bytes (<= 1024) | name (the value's name)            -> M = 180 + name bytes
//   Version 3 (written before version 4 when the tree carried certified errors, else version 2) appends:
//       u32 K (<= 64) | K x (u64 LOD count | f64 max error | f64 Hardy c relative)
//                                                                      -> M = 184 + name bytes + 24 K
//   the counts strictly ascending in 1 .. splits + 1, the errors >= 0 (+inf: the LOD's field is NaN
//   somewhere), the c in (0, 100].
//   Version 4 (written now) always has the version 3 list (K may be 0) and appends to the meta:
//       u64 samples hash (kernels/sample_set_hash.hpp; 0: unknown, a tree first read from an older
//       version's file)                                                -> M = 192 + name bytes + 24 K
//   Version 1 (still read) has no split order, cluster value or size term (M = 164 + name bytes):
//   its trees were built with the dissertation's max-error order and fitted values.
//   u32 CRC-32 of the meta bytes
//   nodes (N x 56 bytes): f64 centre[3] | f64 value | f64 error | u32 count | u32 depth |
//       u32 first child (0 = leaf) | u32 flags (bit 0: skipped split)
//   u32 CRC-32 of the node bytes
//   file bytes = 64 + M + 4 + 56 N + 4 exactly. The file holds no time or path: the same input and
//   options give the same bytes, for any thread count.
// Decoding checks, in order: the magic, the version ("made by a newer/older version"), the header
// CRC, the header fields (header bytes, zero padding), the exact file size (truncated or appended
// bytes) against the declared meta and node sizes (no allocation before the bytes are there), the
// meta CRC and fields, the node CRC, then the tree (kernels/cluster_tree.hpp validate_cluster_tree:
// children in range and after their parent, each referenced once, so no cycles; depths; counts that
// add up to the samples) and the counts the meta claims (splits, skipped, depth, error reached)
// against the nodes.
// Errors: FormatError "PATH: offset N: what" (or "PATH: node I: what"), one line; IoError when the
// file cannot be read or written. Writing is atomic (formats/atomic_file.hpp).
// Thread-safety: reentrant functions.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "kernels/cluster_tree.hpp"

namespace meshless {

inline constexpr std::uint32_t kClusterTreeFileVersion = 4;  ///< the newest read, and the one written
inline constexpr std::size_t kClusterTreeHeaderBytes = 64;
inline constexpr std::size_t kClusterTreeMetaFixedBytes = 180;
inline constexpr std::size_t kClusterTreeMetaFixedBytesV1 = 164;
inline constexpr std::size_t kClusterTreeNodeBytes = 56;
inline constexpr std::size_t kClusterTreeCertifiedBytes = 24;
inline constexpr char kClusterTreeMagic[8] = {'\x89', 'M', 'L', 'H', '\r', '\n', '\x1a', '\n'};

/// Writes `tree` to `path` atomically (tree.stats.seconds and memory_bytes are not stored).
/// InvalidArgument for "-" or a non-regular output; IoError when it cannot be written.
void write_cluster_tree_file(const std::string& path, const ClusterTree& tree);

/// The version a .mlh's header declares (0 when the file cannot be read or is no cluster tree);
/// what `info` shows of a file that read_cluster_tree_file accepted.
std::uint32_t cluster_tree_file_version(const std::string& path);

/// Reads and validates a .mlh (see the checks above); stats.seconds is 0.
ClusterTree read_cluster_tree_file(const std::string& path);

/// The same from bytes in memory (tests, the fuzz target); `name` starts the messages.
ClusterTree parse_cluster_tree_bytes(std::span<const unsigned char> bytes, const std::string& name);

/// The file's bytes (what write_cluster_tree_file writes).
std::string cluster_tree_bytes(const ClusterTree& tree);

/// The split order a .mlh records, from its header and meta alone (version 1: max_error); nullopt
/// for a file that is no readable .mlh (the full reader then says what is wrong). No checksum is
/// checked: a hint for what to do with the file, not its contents.
std::optional<CbtSplitOrder> cluster_tree_split_order(const std::string& path);

/// True when the file starts with the .mlh magic (false for a missing or short file).
bool is_cluster_tree_file(const std::string& path);

}  // namespace meshless
