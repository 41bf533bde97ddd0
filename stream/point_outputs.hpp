// The outputs a graph of points ends in (`meshless isosurface`, `demo`, the multiblock and
// scattered surfaces; dissertation section 3.6 for the picture): a point set (-o: PLY or VTP,
// stream/point_file_sink.hpp), a PNG (--png, stream/splat_sink.hpp), or both through a tee.
// Nothing is collected: memory = the image buffers + the batches in flight (a picture whose
// metadata says `frame points`, the scattered surface, first spools its points to an unlinked
// temporary file, 32 bytes a point, then frames and draws them).
// Throws what the sources, stages and sinks throw (FormatError, IoError naming the file).
#pragma once
#include <functional>
#include <optional>
#include <string>

#include "formats/geometry_format.hpp"
#include "formats/point_stream.hpp"
#include "formats/vtp_writer.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/render_settings.hpp"
#include "stream/stage.hpp"

namespace meshless {

/// A geometry output: where and in which format.
struct GeometryOutput {
    std::string path;
    GeometryFormat format = GeometryFormat::ply;
    VtpOptions vtp;  ///< --vtp-compression; threads set by the command
    std::optional<ColorBy> ply_color;  ///< --ply-color: PLY `red green blue` by value, block or normal
};

/// A graph to run into the outputs: run(draw, sink), draw = the splat stage or null.
using GraphRun = std::function<IsoSplatResult(const Stage* draw, Sink& sink)>;

/// Runs `run` into the point set `out` (PLY or VTP: the one place the point sink is chosen, from
/// GeometryOutput::format, see geometry_output) and/or the PNG `png` (at least one given). Each
/// batch is drawn as it is produced and, with `out`, written to the point file; when the metadata
/// has no frame for the picture (picture_bounds: `frame points`), the batches go to a point spool
/// instead, and the picture frames the spool's bounds and replays it after the run (draw is then null). The PNG's temporary
/// is created before the run (a PNG that cannot be created fails at once); the point file is
/// committed only after the picture is written, then the PNG: a failed picture leaves the previous
/// files as they were. When one output is stdout and its reader goes away (BrokenPipe), the other
/// output is still completed and committed, then BrokenPipe is rethrown (quiet exit). Returns the
/// number of points; the run's result goes to r. parallel_draw = false (the MPI root: batches arrive
/// already made): draw is null and the splat sink draws in consume(). with_blocks: the PLY gets the
/// `block` property from the batches' point_block (the multiblock path).
std::size_t run_to_outputs(const std::optional<GeometryOutput>& out, const std::optional<std::string>& png,
                           const StreamMeta& meta, const RenderSettings& rs, int nthreads, const GraphRun& run,
                           IsoSplatResult& r, bool parallel_draw = true, bool with_blocks = false);

}  // namespace meshless
