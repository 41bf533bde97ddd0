// Point sets streamed in chunks (for conversions whose memory must not grow with the input, such as
// `meshless convert POINTS... -o pts.mlc`, ooc/point_store_writer.hpp): the files of
// read_point_set(paths) in the same order and with the same points, handed over in chunks of
// x, y, z, value records instead of one PointSet.
// Streamed (memory independent of the file's size): PLY (formats/points_ply.hpp) and point stores
// (.mlc, one brick at a time). Every other format is read whole by its reader (read_point_set) and
// then handed over in chunks, so its memory is that file's PointSet (32 bytes a point) for the
// duration of the file.
// NaN/Inf records are dropped and counted (options.strict refuses them), as the readers do; the
// scalar's name and presence must agree between files (FormatError naming the file otherwise).
// Unlike read_point_set, no minimum point count and no extent check (the caller checks the whole).
// Throws what the readers throw; InvalidArgument when `paths` is empty. Reentrant.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"

namespace meshless {

struct PointChunkTotals {
    std::uint64_t points = 0;  ///< handed over
    std::uint64_t dropped_nonfinite = 0, dropped_blanked = 0;
    std::string value_name;
    bool has_values = true;
};

/// chunk(xyzv): finite points, 4 doubles each, in file order then record order; file_done(i) after
/// file i (when given).
PointChunkTotals stream_point_set(const std::vector<std::string>& paths, const PointSetOptions& options,
                                  const std::function<void(std::span<const double> xyzv)>& chunk,
                                  const std::function<void(std::size_t file)>& file_done = {});

}  // namespace meshless
