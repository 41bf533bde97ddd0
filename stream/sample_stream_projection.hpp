// The stage graphs of the pipes (dissertation sections 3.3-3.4; Table 3.1 paradigms B and D; and
// section 4.4 / 5.6 for seeds): a sample stream projected onto the isosurface into a point stream
// (`meshless project`), a seed stream projected onto a meshless field's isosurface
// (`meshless project --field`), and a point stream written as a point file (`meshless write`). Memory: a few batches in flight.
// Throws what the stream reader, the projection and the sinks throw (FormatError naming the
// stream, IoError, BrokenPipe); the bytes do not depend on the thread count.
#pragma once
#include <cstdio>
#include <string>
#include <vector>

#include "formats/point_stream.hpp"
#include "kernels/field.hpp"
#include "kernels/project_sample.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/point_file_sink.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless {

/// Throws unless `reader` holds a sample stream (`meshless generate VOLUME`'s), naming `name`: InvalidArgument
/// for a seed stream (it is projected onto a field: `meshless project --field KIND BLOCKS...`), FormatError
/// for a point stream.
void require_sample_stream(const StreamReader& reader, const std::string& name);

/// Projects every sample `reader` delivers onto f = iso (section 3.3: approx, Eq. 3.5; exact, Eq.
/// 3.3; or none) on `threads` threads, into `sink` (a point stream); returns the projection's counts.
ProjectionStats project_sample_stream(StreamReader& reader, double iso, Projection mode, Sink& sink, int threads);
/// The same into a point stream on `out` (named `out_name`; compress: zstd DATA frames) whose
/// metadata is the samples' (its metadata read) with `iso` and `mode`. FormatError (naming
/// `in_name`) for Projection::exact on the samples of a paradigm (A) sample store: they carry no
/// cell corners.
ProjectionStats project_sample_stream(StreamReader& reader, const std::string& in_name, double iso, Projection mode, std::FILE* out,
                                      const std::string& out_name, bool compress, int threads);
/// A sample stream of several isovalues (its metadata read by a reader that stops at segments:
/// `isovalues` listed, formats/point_stream.hpp "Segments"): each segment's samples projected onto
/// its own isovalue, into a point stream on `out` of the same segments whose metadata is the
/// samples' with `mode`; returns each segment's counts. FormatError (naming `in_name`) for segments
/// that do not match the listed isovalues, and as the one-isovalue form above.
std::vector<ProjectionStats> project_sample_segments(StreamReader& reader, const std::string& in_name, Projection mode,
                                                     std::FILE* out, const std::string& out_name, bool compress, int threads);
/// The statistics line of a sample projection (prefixed `project: `) to `out`.
void print_projection_stats(std::FILE* out, Projection mode, const ProjectionStats& s);

/// What projecting seeds took: the Newton counts and the stage's summed busy time (seconds).
struct SeedProjectionResult {
    FieldNewtonStats stats;
    double busy_seconds = 0;
};

/// Throws FormatError (naming `name`) unless `reader` holds a seed stream (`meshless generate`'s).
void require_seed_stream(const StreamReader& reader, const std::string& name);

/// Projects every seed `reader` delivers (its metadata read) onto field = iso (sections 4.4, 5.6:
/// Newton steps along the gradient, FieldProjectStage) on `threads` threads, into a point stream
/// on `out` (named `name`; compress: zstd DATA frames). Its metadata: the seeds' with iso, the
/// projection's keys and the frame widened for np's travel; its points carry the block they were
/// seeded in unless the seeds are scattered (method=scattered).
SeedProjectionResult project_seed_stream(StreamReader& reader, const Field& field, double iso, const FieldProjectParams& np,
                                         std::FILE* out, const std::string& name, bool compress, int threads);

/// Throws FormatError (naming `name`, and the command that projects them) unless `reader` holds a
/// point stream (projected points).
void require_point_stream(const StreamReader& reader, const std::string& name);

/// Writes every point `reader` delivers to `sink` (PLY or VTP), in stream order.
void write_point_stream(StreamReader& reader, PointFileSink& sink);

}  // namespace meshless
