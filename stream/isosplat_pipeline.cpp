#include "stream/isosplat_pipeline.hpp"

#include <chrono>
#include <cstdio>
#include <vector>

#include "formats/terminal_safe.hpp"
#include "stream/brick_source.hpp"
#include "stream/cell_row_source.hpp"
#include "stream/generate_project_stage.hpp"
#include "stream/generate_stage.hpp"
#include "stream/project_stage.hpp"
#include "stream/slab_source.hpp"
#include "stream/seconds_since.hpp"

namespace meshless {

namespace {

/// [extra.first] + middle + [extra.last]: the stages present, in order.
std::vector<const Stage*> with_extras(std::initializer_list<const Stage*> middle, const IsoSplatStages& extra) {
    std::vector<const Stage*> v;
    if (extra.first) v.push_back(extra.first);
    v.insert(v.end(), middle.begin(), middle.end());
    if (extra.before_last) v.push_back(extra.before_last);
    if (extra.last) v.push_back(extra.last);
    return v;
}

IsoSplatResult run_regular(Source& source, const VolumeView& v, double iso, Projection mode, const SamplingParams& sp,
                           Sink& sink, const RunOptions& opt, PipelineShape shape, const IsoSplatStages& extra) {
    const auto t0 = std::chrono::steady_clock::now();
    IsoSplatResult r;
    if (shape == PipelineShape::fused) {
        GenerateProjectStage stage(v, iso, sp, mode);
        run_pipeline(source, with_extras({&stage}, extra), sink, opt);
        r.sampling = stage.sampling_stats();
        r.projection = stage.projection_stats();
    } else {
        GenerateStage generate(v, iso, sp);
        ProjectStage project(iso, mode);
        run_pipeline(source,
                     shape == PipelineShape::two_stage ? with_extras({&generate, &project}, extra)
                                                       : with_extras({&generate}, extra),
                     sink, opt);
        r.sampling = generate.stats();
        r.projection = project.stats();
    }
    r.seconds = seconds_since(t0);
    return r;
}

}  // namespace

IsoSplatResult run_isosplat(const VolumeView& v, double iso, Projection mode, const SamplingParams& sp,
                            Sink& sink, const RunOptions& opt, PipelineShape shape, const IsoSplatStages& extra) {
    CellRowSource source(v.grid);
    return run_regular(source, v, iso, mode, sp, sink, opt, shape, extra);
}

IsoSplatResult run_isosplat_slabs(SliceSource& slices, double iso, Projection mode, const SamplingParams& sp,
                                  Sink& sink, const RunOptions& opt, PipelineShape shape, const IsoSplatStages& extra) {
    SlabSource source(slices);
    return run_regular(source, VolumeView{nullptr, slices.type(), slices.grid()}, iso, mode, sp, sink, opt, shape,
                       extra);
}

IsoSplatResult run_isosplat_bricks(const BrickStore& store, BrickCache& cache, std::vector<std::size_t> bricks,
                                   double iso, Projection mode, const SamplingParams& sp, Sink& sink,
                                   const RunOptions& opt, PipelineShape shape, const IsoSplatStages& extra) {
    const auto t0 = std::chrono::steady_clock::now();
    BrickSource source(store, std::move(bricks));
    BrickGenerateStage stage(store, cache, iso, sp,
                             shape == PipelineShape::fused ? std::optional<Projection>(mode) : std::nullopt);
    ProjectStage project(iso, mode);
    run_pipeline(source,
                 shape == PipelineShape::two_stage ? with_extras({&stage, &project}, extra) : with_extras({&stage}, extra),
                 sink, opt);
    IsoSplatResult r;
    r.sampling = stage.sampling_stats();
    r.projection = shape == PipelineShape::two_stage ? project.stats() : stage.projection_stats();
    r.seconds = seconds_since(t0);
    return r;
}

IsoSplatResult run_isosplat_sample_store(SampleStoreSource& source, double iso, Projection mode, Sink& sink,
                                         const RunOptions& opt, PipelineShape shape, const IsoSplatStages& extra) {
    const auto t0 = std::chrono::steady_clock::now();
    const ProjectStage project(iso, mode);
    run_pipeline(source, shape == PipelineShape::samples_only ? with_extras({}, extra) : with_extras({&project}, extra),
                 sink, opt);
    IsoSplatResult r;
    r.seconds = seconds_since(t0);
    r.sampling.active_cells = static_cast<std::int64_t>(source.emitted());
    if (shape != PipelineShape::samples_only) r.projection = project.stats();
    return r;
}

void print_isosplat_stats(std::FILE* out, const std::string& path, double iso, Projection mode, const IsoSplatResult& r,
                          std::size_t points, int nthreads, int ranks) {
    std::fprintf(out,
                 "isosurface: %s iso %g: %lld active cells, %zu points (%s projection; discarded: %lld too far, %lld flat, "
                 "%lld missed; %lld cells with NaN/Inf skipped), %.3f s on %d thread(s) x %d rank(s)\n",
                 terminal_safe(path).c_str(), iso, static_cast<long long>(r.sampling.active_cells), points, to_string(mode),
                 static_cast<long long>(r.projection.too_far), static_cast<long long>(r.projection.flat),
                 static_cast<long long>(r.projection.missed), static_cast<long long>(r.sampling.nonfinite_cells), r.seconds,
                 nthreads, ranks);
}

}  // namespace meshless
