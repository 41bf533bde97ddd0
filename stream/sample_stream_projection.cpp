#include "stream/sample_stream_projection.hpp"

#include "stream/project_stage.hpp"
#include "stream/runner.hpp"

namespace meshless {

ProjectionStats project_sample_stream(StreamReader& reader, double iso, Projection mode, StreamSink& sink, int threads) {
    StreamSource source(reader);
    ProjectStage project(iso, mode);
    const Stage* stages[] = {&project};
    run_pipeline(source, stages, sink, {threads});
    return project.stats();
}

SeedProjectionResult project_seed_stream(StreamReader& reader, const Field& field, double iso, const FieldProjectParams& np,
                                         StreamSink& sink, int threads) {
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
