#include "stream/isosplat_pipeline.hpp"

#include <chrono>

#include "stream/cell_row_source.hpp"
#include "stream/generate_project_stage.hpp"
#include "stream/generate_stage.hpp"
#include "stream/project_stage.hpp"

namespace meshless {

IsoSplatResult run_isosplat(const VolumeView& v, double iso, Projection mode, const SamplingParams& sp,
                            Sink& sink, const RunOptions& opt, bool opt_fused) {
    const auto t0 = std::chrono::steady_clock::now();
    CellRowSource source(v.grid);
    IsoSplatResult r;
    if (opt_fused) {
        GenerateProjectStage stage(v, iso, sp, mode);
        const Stage* stages[] = {&stage};
        run_pipeline(source, stages, sink, opt);
        r.sampling = stage.sampling_stats();
        r.projection = stage.projection_stats();
    } else {
        GenerateStage generate(v, iso, sp);
        ProjectStage project(iso, mode);
        const Stage* stages[] = {&generate, &project};
        run_pipeline(source, stages, sink, opt);
        r.sampling = generate.stats();
        r.projection = project.stats();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace meshless
