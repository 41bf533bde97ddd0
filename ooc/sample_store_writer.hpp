// Paradigm (A) preprocessing (dissertation section 3.5, Table 3.1): builds the sample store of a
// brick store (`meshless generate vol.mlb --all -o vol.mls`; layout in ooc/sample_store_format.hpp).
// Every non-constant cell whose eight corners are finite is filed, by its cell row, under the
// span-space bucket of its value interval [vmin, vmax] (ooc/span_space_levels.hpp).
// Two passes over the bricks in Morton order, one brick in memory at a time: the first counts the
// keys and key bytes per bucket, the second encodes them and writes each bucket's run at its place
// (positional writes into an AtomicFile: temporary name, then rename). Memory: O(buckets) plus one
// brick plus a bounded buffer of pending keys, never all keys.
// Errors: InvalidArgument (output "-", levels out of 1..1024, an .mlb path too long to record),
// FormatError (damaged bricks, naming the .mlb), IoError (cannot write). Not thread-safe (one call
// writes one file); the store must not change while it runs.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "ooc/brick_store.hpp"

namespace meshless {

struct SampleStoreParams {
    std::uint32_t levels = 256;             ///< span-space levels L (1..1024); integer data with <= L values: exact
    std::size_t buffer_keys = 1u << 20;     ///< pending keys before a sorted flush (memory: 16 bytes each)
    std::function<void(double)> progress;   ///< optional: the fraction done (0..1), after each brick of each pass
};

struct SampleStoreBuildStats {
    std::uint64_t cells = 0, keys = 0, buckets = 0, constant_cells = 0, nonfinite_cells = 0;
    std::uint64_t file_bytes = 0;
    std::uint32_t levels = 0;
    bool exact_levels = false;
};

/// The one-line report of a build (`meshless generate VOL.mlb --all -o vol.mls --stats`, no newline):
/// "generate --all: SOURCE: N non-constant cells as K cell-row keys in B span-space buckets (L levels[, exact]),
/// C constant and F NaN/Inf cells skipped, S MiB" (S = file bytes / 2^20; SOURCE made terminal_safe).
std::string sample_store_stats_line(const SampleStoreBuildStats& st, const std::string& source);

/// Writes the sample store of `store` (opened from store.path()) to `path`; the .mls records the
/// .mlb's path relative to the .mls's folder (absolute when no relative path exists) and its identity.
SampleStoreBuildStats write_sample_store(const BrickStore& store, const std::string& path,
                                         const SampleStoreParams& params = {});

}  // namespace meshless
