// The sample recipe, what `meshless sample` runs (and any other front end): scattered points from a
// volume, uniform random positions in its bounds with values by trilinear interpolation
// (dissertation Eq. 3.1), as the paper made its scattered buckyball set (chapter 4). Deterministic
// for a seed (its own generator and conversion, kernels/splitmix.hpp; no std distributions): the
// points are the first `count` draws with a finite value, so they do not depend on how they are
// chunked, nor on whether the volume is in memory or a brick store.
// Positions falling in cells with a NaN corner are redrawn and counted.
// Streaming (sample_volume_chunks, sample_volume_to_file): the points go out in chunks, memory is
// kSampleChunkBytes a point of one chunk plus the volume's (a brick store: its cache), whatever the count.
// Units: world coordinates.
// Throws FormatError naming `name` when NaN/Inf cells leave too few finite positions (more than
// 20 draws a point); what the evaluation and the writer throw.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "kernels/grid.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

class BrickStore;

struct VolumeSample {
    PointSet points;           ///< value name "value", one block "sample"
    std::uint64_t redrawn = 0;  ///< positions in cells with NaN/Inf corners, drawn again
};

/// `count` (>= 1) points of `v` drawn with `seed`; `name` (the volume's file) names it in errors.
VolumeSample sample_volume(const Volume& v, std::uint64_t count, std::uint64_t seed, const std::string& name);

/// Trilinear values at positions (value.size() == pos.size()).
using SampleValues = std::function<void(std::span<const Vec3> pos, std::span<double> value)>;

/// The same points, drawn in `grid`'s bounds with values from `values`, handed to emit(pos, value)
/// `chunk` (>= 1) at a time (the last chunk may be shorter). Returns the positions redrawn.
std::uint64_t sample_volume_chunks(const GridSpec& grid, const SampleValues& values, std::uint64_t count, std::uint64_t seed,
                                   const std::string& name, std::size_t chunk,
                                   const std::function<void(std::span<const Vec3>, std::span<const double>)>& emit);

/// Bytes a point of a chunk takes while it is drawn, evaluated (grouped by brick) and written.
inline constexpr std::uint64_t kSampleChunkBytes = 112;

/// What sample_volume_to_file reads from: a volume in memory, or a brick store read brick by brick
/// (the positions of a chunk grouped by brick, ooc/brick_store_values.hpp) within `memory_bytes`:
/// half for the brick cache (one brick at least), half for the chunk (65,536 to 4 Mi points).
struct SampleInput {
    const Volume* volume = nullptr;
    const BrickStore* store = nullptr;
    std::uint64_t memory_bytes = 256ull << 20;
};

/// Writes the `count` points to `path` (formats/point_set_writer.hpp PointSetWriter: PLY, CSV or VTP
/// by extension, "-" CSV on stdout; temporary name and rename) chunk by chunk, with `comments`
/// (a volume with too few finite cells fails as it is found out: a file is then removed, while stdout
/// has already had the chunks drawn before)
/// (PLY/VTP provenance). progress(k): k more points written (may be empty). chunk: points a chunk
/// (0: from in.memory_bytes as above; the points do not depend on it). Returns the positions redrawn.
std::uint64_t sample_volume_to_file(const SampleInput& in, std::uint64_t count, std::uint64_t seed, const std::string& name,
                                    const std::string& path, const std::vector<std::string>& comments,
                                    const std::function<void(double)>& progress = {}, std::size_t chunk = 0);

}  // namespace meshless
