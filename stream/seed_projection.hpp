// The second half of the chapter-4 and chapter-5 isosurface graphs (dissertation sections 4.4 and
// 5.6): the source's work units -> a progress counter -> the seed stage (marching-cubes seeds of
// blocks, stream/block_seed_stage.hpp, or of stencils, stream/stencil_seed_stage.hpp) ->
// safeguarded Newton onto the field (stream/field_project_stage.hpp) [-> draw] -> the sink, through
// the runner. One graph for both recipes (stream/block_isosurface.hpp, stream/scattered_isosurface.hpp),
// and the statistics line of its Newton projection that both print (to any FILE*).
// Throws what the stages and the sink throw.
#pragma once
#include <cstdio>
#include <functional>
#include <span>
#include <string>

#include "formats/point_stream.hpp"
#include "kernels/field.hpp"
#include "stream/field_data.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/progress_stage.hpp"
#include "stream/runner.hpp"

namespace meshless {

/// What the projection did, and the stages' busy time (summed over threads).
struct SeedProjection {
    FieldNewtonStats newton;
    double seed_busy_seconds = 0, newton_busy_seconds = 0;
};

/// progress(k): k more work units handed out by the source (may be empty). SeedStage: a Stage with
/// busy_seconds(); its statistics stay with the caller's stage.
template <class SeedStage>
SeedProjection run_seed_projection(Source& source, const SeedStage& seed, const Field& field, double iso,
                                   const FieldProjectParams& np, const Stage* draw, Sink& sink, const RunOptions& opt,
                                   const std::function<void(double)>& progress) {
    const FieldProjectStage project(field, iso, np);
    const ProgressStage counter([&](double k) { if (progress) progress(k); }, work_units);
    const Stage* stages[] = {&counter, &seed, &project, draw};
    run_pipeline(source, std::span<const Stage* const>(stages, draw ? 4 : 3), sink, opt);
    return {project.stats(), seed.busy_seconds(), project.busy_seconds()};
}

/// The field and metadata of an isosurface job (stream/block_isosurface.hpp fit_block_field,
/// stream/scattered_isosurface.hpp fit_scattered_field).
struct IsosurfaceField {
    BuiltField field;    ///< empty when the isovalue crosses no data (an empty output needs none)
    std::string name;    ///< the built field's name, else the kind the caller named
    double seconds = 0;  ///< the build's own time
    StreamMeta meta;     ///< the recipe's metadata, for an isosurface with the projection's keys
};

/// The wall times (seconds) a front end measured around an isosurface run, for its statistics:
/// the field's build, the graph, the whole command.
struct IsosurfaceRunTimes {
    double field = 0, graph = 0, total = 0;
};

/// The statistics line of the Newton projection (`cmd`: the line's prefix, `field`: the field's
/// name, busy_seconds: the projection's busy time, 0 when unknown) written to `out`.
void print_newton_stats(std::FILE* out, const char* cmd, const std::string& field, const FieldProjectParams& p,
                        const FieldNewtonStats& s, double busy_seconds);

}  // namespace meshless
