#include "stream/sample_stream_projection.hpp"

#include "kernels/errors.hpp"
#include "stream/continued_sink.hpp"
#include "stream/project_stage.hpp"
#include "stream/projection_meta.hpp"
#include "stream/runner.hpp"
#include "stream/stream_metadata.hpp"

namespace meshless {

ProjectionStats project_sample_stream(StreamReader& reader, double iso, Projection mode, Sink& sink, int threads) {
    StreamSource source(reader);
    ProjectStage project(iso, mode);
    const Stage* stages[] = {&project};
    run_pipeline(source, stages, sink, {threads});
    return project.stats();
}

namespace {
void check_corners(const StreamMeta& meta, const std::string& in_name, Projection mode) {
    if (mode == Projection::exact && meta.get("sample_corners") == "none")
        throw FormatError(in_name + ": samples from a paradigm (A) sample store carry no cell corners; "
                          "--projection exact needs them, use approx");
}
}  // namespace

ProjectionStats project_sample_stream(StreamReader& reader, const std::string& in_name, double iso, Projection mode, std::FILE* out,
                                      const std::string& out_name, bool compress, int threads) {
    StreamMeta meta = reader.meta();
    check_corners(meta, in_name, mode);
    meta.set("iso", iso);
    meta.set("projection", to_string(mode));
    StreamSink sink(out, out_name, RecordKind::point, meta, compress);
    const ProjectionStats s = project_sample_stream(reader, iso, mode, sink, threads);
    if (reader.segments() != 0)  // (a reader stopping at segments ends there)
        throw FormatError(in_name + ": a segment frame in a stream of one isovalue (its metadata lists no isovalues)");
    return s;
}

std::vector<ProjectionStats> project_sample_segments(StreamReader& reader, const std::string& in_name, Projection mode,
                                                     std::FILE* out, const std::string& out_name, bool compress, int threads) {
    StreamMeta meta = reader.meta();
    check_corners(meta, in_name, mode);
    const std::vector<double> isos = meta_isovalues(meta).value();
    meta.set("projection", to_string(mode));
    StreamSink sink(out, out_name, RecordKind::point, meta, compress);
    std::vector<ProjectionStats> r;
    ContinuedSink continued(sink);
    while (const auto seg = reader.next_segment()) {
        const std::size_t k = r.size();
        const std::optional<double> iso = seg->get_finite("iso");
        if (k >= isos.size() || !iso || *iso != isos[k])
            throw FormatError(in_name + ": segment " + std::to_string(k) + " does not begin isovalue " + std::to_string(k + 1) +
                              " of the " + std::to_string(isos.size()) + " its metadata lists (" + *meta.get("isovalues") + ")");
        sink.begin_segment(k, *iso);
        r.push_back(project_sample_stream(reader, *iso, mode, continued, threads));
    }
    if (r.size() != isos.size())
        throw FormatError(in_name + ": holds " + std::to_string(r.size()) + " segments for the " + std::to_string(isos.size()) +
                          " isovalues its metadata lists (truncated or corrupt stream)");
    sink.finish();
    return r;
}

void print_projection_stats(std::FILE* out, Projection mode, const ProjectionStats& s) {
    std::fprintf(out, "project: %lld samples -> %lld points (%s; discarded: %lld too far, %lld flat, %lld missed)\n",
                 static_cast<long long>(s.input), static_cast<long long>(s.output), to_string(mode),
                 static_cast<long long>(s.too_far), static_cast<long long>(s.flat), static_cast<long long>(s.missed));
}

void require_sample_stream(const StreamReader& reader, const std::string& name) {
    if (reader.kind() == RecordKind::seed)
        throw InvalidArgument(name + ": holds multiblock seeds; project them onto a field: meshless project --field KIND BLOCKS...");
    if (reader.kind() != RecordKind::sample)
        throw FormatError(name + ": holds projected points, expected a sample stream from 'meshless generate'");
}

void require_point_stream(const StreamReader& reader, const std::string& name) {
    if (reader.kind() != RecordKind::point)
        throw FormatError(name + (reader.kind() == RecordKind::seed ? ": holds unprojected seeds; run 'meshless project --field KIND BLOCKS...' first"
                                                                   : ": holds unprojected samples; run 'meshless project' first"));
}

void require_seed_stream(const StreamReader& reader, const std::string& name) {
    if (reader.kind() != RecordKind::seed)
        throw FormatError(name + ": not a seed stream; --field projects the seeds of 'meshless generate BLOCKS...' "
                          "(sample streams are projected without --field)");
}

SeedProjectionResult project_seed_stream(StreamReader& reader, const Field& field, double iso, const FieldProjectParams& np,
                                         std::FILE* out, const std::string& name, bool compress, int threads) {
    StreamMeta meta = reader.meta();
    meta.set("iso", iso);
    add_projection_meta(meta, field.name(), np);
    widen_frame_for_travel(meta, np.seed_max_travel);
    // multiblock seeds carry block ids; scattered ones (stream/scattered_isosurface.hpp) do not
    const bool with_blocks = meta.get("method").value_or("") != "scattered";
    StreamSink sink(out, name, RecordKind::point, meta, compress, with_blocks);
    StreamSource source(reader);
    FieldProjectStage project(field, iso, np);
    const Stage* stages[] = {&project};
    run_pipeline(source, stages, sink, {threads});
    return {project.stats(), project.busy_seconds()};
}

void write_point_stream(StreamReader& reader, PointFileSink& sink) {
    StreamSource source(reader);
    run_pipeline(source, {}, sink, {1});
}

}  // namespace meshless
