#include "stream/isosplat_pipeline.hpp"

#include <chrono>

#include "stream/cell_row_source.hpp"
#include "stream/generate_stage.hpp"
#include "stream/project_stage.hpp"

namespace meshless {

IsoSplatResult run_isosplat(const VolumeView& v, double iso, Projection mode, const SamplingParams& sp,
                            Sink& sink, const RunOptions& opt) {
    const auto t0 = std::chrono::steady_clock::now();
    CellRowSource source(v.grid);
    GenerateStage generate(v, iso, sp);
    ProjectStage project(iso, mode);
    const Stage* stages[] = {&generate, &project};
    run_pipeline(source, stages, sink, opt);
    IsoSplatResult r;
    r.sampling = generate.stats();
    r.projection = project.stats();
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace meshless
