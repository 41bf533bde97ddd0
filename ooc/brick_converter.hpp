// Slab-streaming conversion of a volume into a brick store (docs/architecture.md "Brick store"): one pass
// over z-slabs of B+1 slices (memory: one slab of bricks plus its compressed frames, never the
// volume), compressed bricks spooled to "<out>.tmp-<pid>.spool", then written in Morton order with
// the index and footer to "<out>.tmp-<pid>" and renamed over <out>. Deterministic: the same input
// and parameters give byte-identical stores, so a conversion killed at any point and run again
// yields the same file; a killed run leaves only temporaries, never a file that looks complete,
// and the next conversion to the same <out> removes temporaries whose process no longer exists.
// Bricks of a slab are compressed in parallel (oneTBB, `threads` workers); output bytes do not
// depend on the thread count.
// Throws IoError (disk full, unwritable) after removing its temporaries; FormatError from the source;
// InvalidArgument for ConvertParams out of range or a volume needing 2^21 or more bricks along an axis.
#pragma once
#include <cstdint>
#include <functional>
#include <array>
#include <optional>
#include <string>

#include "ooc/slice_source.hpp"

namespace meshless {

struct ConvertParams {
    std::uint32_t brick_edge = 32;  ///< cells per brick edge (2..1024); InvalidArgument otherwise
    int zstd_level = 1;             ///< 1..ZSTD_maxCLevel(); default chosen by benchmark (numbers in cli/cmd_convert.cpp)
    int threads = 1;                ///< compression threads (>= 1); output bytes do not depend on it
    /// The source's patient axes (LPS direction of world +x, +y, +z), recorded in the header
    /// (BrickStoreInfo::patient_axes) when given.
    std::optional<std::array<std::array<double, 3>, 3>> patient_axes;
    /// The source's length unit (formats/length_unit.hpp), recorded as BrickStoreInfo::length_unit.
    std::string length_unit;
    /// The source's values' unit (formats/length_unit.hpp value_unit_text), recorded as BrickStoreInfo::value_unit.
    std::string value_unit;
};

struct ConvertStats {
    std::uint64_t input_bytes = 0;   ///< voxels * sample size
    std::uint64_t output_bytes = 0;  ///< size of the store
    std::uint64_t bricks = 0;
    double seconds = 0;
};

/// progress(fraction) is called after each slab when given (the CLI prints it on a terminal).
ConvertStats convert_to_brick_store(SliceSource& src, const std::string& out_path, const ConvertParams& p,
                                    const std::function<void(double)>& progress = {});

}  // namespace meshless
