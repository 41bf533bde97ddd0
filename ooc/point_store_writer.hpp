// Conversion of point sets into a point store (.mlc, formats/point_store_format.hpp): the Morton
// point store of `meshless convert POINTS... -o pts.mlc` (dissertation section 3.6's Morton on-disk
// order applied to the scattered inputs of chapters 4-5).
//
// Algorithm (external sort when the points do not fit in the memory budget):
//  1. Read the inputs in chunks (formats/point_set_chunks.hpp), dropping and counting NaN/Inf
//     records, keeping the finite ones as 48-byte records (key, input index, x, y, z, value) and
//     accumulating bounds and value range. While they fit in the budget they stay in memory;
//     beyond it they are appended, unsorted, to the spool "<out>.tmp-<pid>.spool".
//  2. Key every record (PointStoreGrid over the bounds, level 21) and sort by (key, input index):
//     in memory (oneTBB parallel sort) when nothing was spilled; else the spooled records are
//     sorted in runs of the budget's size, appended to the spool, and k-way merged (in several
//     passes when one pass would leave each run less than a 48 KiB buffer).
//  3. Cut the sorted stream into bricks, the non-empty leaves of the octree that splits a cell
//     while it holds more than B points: the brick of the first unassigned point is the largest
//     aligned cell around it that holds no earlier point and at most B points (found with a
//     lookahead of B + 1 records); a level-L cell with more than B points is cut into bricks of B.
//     Bricks are compressed in parallel batches (zstd, `threads` workers) and written in order to
//     "<out>.tmp-<pid>", then the index, footer and final header; fsync and rename (AtomicFile).
// Memory: records, sort and merge buffers, and the brick batches stay within params.memory_bytes
// (the point-set readers of formats that are not streamed (all but PLY and .mlc) hold their own
// file whole; the index, 112 bytes a brick, is kept in memory besides). InvalidArgument when the
// budget cannot hold the brick pipeline and a minimal sort buffer ("--memory ... too small").
// Determinism: the same inputs and params give the same bytes for any thread count and any memory
// budget that runs (the order (key, input index) is total; bricks depend on it alone).
// Signals: the spool and the output temporary are registered (formats/temporary_files.hpp), so the
// CLI's handlers remove them; a killed run leaves only temporaries, swept by the next conversion.
// Throws FormatError/IoError from the readers; FormatError when fewer than 4 finite points remain
// or they span more than 1e150 units; IoError writing (temporaries removed); InvalidArgument for
// parameters out of range. Not thread-safe (one conversion per call; it uses `threads` workers).
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "formats/point_set_chunks.hpp"
#include "formats/point_set_options.hpp"
#include "formats/point_store_format.hpp"

namespace meshless {

struct PointStoreParams {
    std::uint32_t brick_points = 4096;           ///< B, 1..2^20
    int zstd_level = 1;                          ///< 1..ZSTD_maxCLevel()
    int threads = 1;                             ///< >= 1; bytes do not depend on it
    std::uint64_t memory_bytes = 256ull << 20;   ///< the budget (see above)
    std::uint32_t level = kPointStoreMaxLevel;   ///< L, Morton bits per axis (1..21; tests use less)
};

struct PointStoreStats {
    std::uint64_t points = 0, dropped_nonfinite = 0, dropped_blanked = 0;
    std::uint64_t bricks = 0;
    std::uint64_t runs = 0;          ///< sorted runs spilled (0: sorted in memory)
    std::uint64_t merge_passes = 0;  ///< intermediate merge passes (0 or more) before the final one
    std::uint64_t output_bytes = 0;
    double seconds = 0;
};

/// The one-line report of a conversion (`meshless convert POINTS -o pts.mlc --stats`, no newline):
/// "convert: N points (K NaN/Inf dropped) -> OUTPUT: B bricks of at most P points, R sorted run(s)
/// spilled, S MB in T s" (MB = 10^6 bytes of output, T wall seconds; OUTPUT made terminal_safe).
std::string point_store_stats_line(const PointStoreStats& st, const std::string& output, std::uint32_t brick_points);

/// progress(phase, done, total): phase "read" (points read; total 0 = unknown), "sort" (runs
/// sorted or merged), "write" (points written of total).
using PointStoreProgress = std::function<void(const char* phase, std::uint64_t done, std::uint64_t total)>;

/// The point chunks of the input: calls chunk(xyzv) (finite points only) and returns the totals.
using PointChunkProducer =
    std::function<PointChunkTotals(const std::function<void(std::span<const double> xyzv)>& chunk)>;

/// Converts the points `produce` hands over; `source` is recorded in the header (file names).
PointStoreStats convert_points_to_point_store(const PointChunkProducer& produce, const std::string& source,
                                              const std::string& out_path, const PointStoreParams& params,
                                              const PointStoreProgress& progress = {});

/// The files `paths` read as one point set (stream_point_set; source = their file names).
PointStoreStats convert_to_point_store(const std::vector<std::string>& paths, const PointSetOptions& options,
                                       const std::string& out_path, const PointStoreParams& params,
                                       const PointStoreProgress& progress = {});

/// The smallest budget that runs with these params (for messages and tests).
std::uint64_t point_store_min_memory(const PointStoreParams& params);

}  // namespace meshless
