#include "cli/isosurface_graph.hpp"

#include <chrono>
#include <cstdio>
#include <span>
#include <vector>

#include "formats/atomic_file.hpp"
#include "formats/png_writer.hpp"
#include "kernels/cell_sampling.hpp"
#include "stream/brick_source.hpp"
#include "stream/cell_row_source.hpp"
#include "stream/generate_project_stage.hpp"
#include "stream/point_file_sink.hpp"
#include "stream/runner.hpp"
#include "stream/slab_source.hpp"
#include "stream/splat_sink.hpp"
#include "stream/tee_sink.hpp"

namespace meshless::cli {

namespace {
/// [progress] + generate + [draw]: the stages present, in order.
std::vector<const Stage*> stage_list(const Stage* progress, const Stage& generate, const Stage* draw) {
    std::vector<const Stage*> v;
    if (progress) v.push_back(progress);
    v.push_back(&generate);
    if (draw) v.push_back(draw);
    return v;
}
}  // namespace

double isosurface_work(const VolumeInput& in, double iso) {
    if (!in.store) return static_cast<double>(cell_row_count(in.grid()));
    double rows = 0;
    for (const std::size_t b : in.index->active(iso)) rows += static_cast<double>(cell_row_count(in.store->brick_grid(b)));
    return rows;
}

IsoSplatResult run_isosurface_graph(VolumeInput& in, double iso, Projection mode, const SamplingParams& sp,
                                    const Stage* draw, Sink& sink, int nthreads, const Stage* progress) {
    const auto t0 = std::chrono::steady_clock::now();
    IsoSplatResult r;
    if (in.store) {
        BrickSource source(*in.store, in.index->active(iso));
        BrickGenerateStage generate(*in.store, *in.cache, iso, sp, mode);
        run_pipeline(source, stage_list(progress, generate, draw), sink, {nthreads});
        r.sampling = generate.sampling_stats();
        r.projection = generate.projection_stats();
    } else {
        // slab-streamed file (stream/slab_source.hpp; batches carry their chunk) or a volume in memory
        std::optional<SlabSource> slabs;
        std::optional<CellRowSource> rows;
        Source& source = in.slices ? static_cast<Source&>(slabs.emplace(*in.slices)) : rows.emplace(in.grid());
        GenerateProjectStage generate(in.slices ? VolumeView{nullptr, in.type(), in.grid()} : in.volume->view(), iso, sp, mode);
        run_pipeline(source, stage_list(progress, generate, draw), sink, {nthreads});
        r.sampling = generate.sampling_stats();
        r.projection = generate.projection_stats();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

namespace {
/// The picture's colour settings with the colouring --ply-color asks for (range, colour map as the picture's).
std::optional<ShadingParams> ply_colors(const GeometryOutput& out, const RenderSettings& rs) {
    if (!out.ply_color) return std::nullopt;
    ShadingParams s = rs.shading;
    s.color_by = *out.ply_color;
    return s;
}
}  // namespace

std::size_t run_to_outputs(const std::optional<GeometryOutput>& out, const std::optional<std::string>& png,
                           const StreamMeta& meta, const RenderSettings& rs, int nthreads, const GraphRun& run,
                           IsoSplatResult& r, bool parallel_draw, bool with_blocks) {
    if (!png) {
        VtpOptions vo = out->vtp;
        if (vo.threads == 0) vo.threads = nthreads;
        PointFileSink sink(out->path, out->format, ply_comments(meta), vo, with_blocks, ply_colors(*out, rs));
        r = run(nullptr, sink);
        return sink.count();
    }
    SplatSink splat(rs.camera, rs.kernel, rs.shading, *meta_bounds(meta), nthreads);
    std::optional<PointFileSink> ply;
    if (out) {
        VtpOptions vo = out->vtp;
        if (vo.threads == 0) vo.threads = nthreads;
        ply.emplace(out->path, out->format, ply_comments(meta), vo, with_blocks, ply_colors(*out, rs));
    }
    std::optional<TeeSink> tee;
    if (ply) tee.emplace(splat, *ply);
    r = run(parallel_draw ? &splat.stage() : nullptr, tee ? static_cast<Sink&>(*tee) : splat);
    try {
        Image picture = splat.image();
        decorate_picture(rs, picture);
        write_png(picture, *png);
    } catch (...) {
        if (out && !is_streaming_output(out->path)) std::remove(out->path.c_str());
        throw;
    }
    return splat.points();
}

}  // namespace meshless::cli
