#include "stream/isosplat_job.hpp"

#include <cmath>

#include "ooc/sample_store.hpp"
#include "stream/iso_range_warning.hpp"
#include "stream/sample_store_source.hpp"
#include "stream/stream_metadata.hpp"

namespace meshless {

namespace {

/// The picture of points whose metadata records their volume: its patient axes for the default
/// camera and, without a given range, its value range for the value colours — what splat of the
/// same points' PLY or stream draws.
RenderSettings picture_from_meta(const IsosplatJob& j, const StreamMeta& meta) {
    RenderSettings rs = j.rs;
    if (const auto f = meta_patient_axes(meta); f && j.anatomical_camera) j.anatomical_camera(*f, rs.camera);
    if (!j.range_given) {
        rs.shading.value_lo = meta.get_double("value_min").value_or(j.iso);
        rs.shading.value_hi = meta.get_double("value_max").value_or(j.iso);
    }
    return rs;
}

}  // namespace

std::size_t run_isosplat_job(const IsosplatJob& j, VolumeInput& in) {
    RenderSettings rs = j.rs;
    // head up, face to the viewer, where the header says
    if (j.png && !j.up_given && in.frame && j.anatomical_camera) j.anatomical_camera(*in.frame, rs.camera);
    StreamMeta meta = volume_meta(in, j.iso, j.producer);  // value range and surface bounds, one pass
    if (!j.range_given) {
        rs.shading.value_lo = meta.get_double("value_min").value_or(j.iso);
        rs.shading.value_hi = meta.get_double("value_max").value_or(j.iso);
    }
    const bool said = warn_if_iso_outside(j.iso, {meta.get_double("value_min").value_or(NAN), meta.get_double("value_max").value_or(NAN)}, in.path);
    if (j.warned) *j.warned = said;
    meta.set("projection", to_string(j.mode));
    IsoSplatResult r;
    std::size_t points = 0;
    {  // (the progress display goes before the statistics)
        const auto counted = j.progress ? j.progress("cell rows", isosurface_work(in, j.iso)) : std::function<void(double)>();
        const ProgressStage progress([&](double n) { if (counted) counted(n); }, work_units);
        points = run_to_outputs(j.out(), j.png, meta, rs, j.threads, [&](const Stage* draw, Sink& sink) {
            return run_isosplat_input(in, j.iso, j.mode, j.sp, sink, j.threads, PipelineShape::fused, {&progress, draw});
        }, r);
    }
    if (j.stats) print_isosplat_stats(j.stats, in.path, j.iso, j.mode, r, points, j.threads, 1);
    return points;
}

std::size_t run_isosplat_sample_store_job(const IsosplatJob& j, const std::string& path) {
    const auto store = SampleStore::open(path);
    const bool said = warn_if_iso_outside(j.iso, {store->info().value_lo, store->info().value_hi}, path);
    if (j.warned) *j.warned = said;
    StreamMeta meta = sample_store_meta(*store, j.iso, j.producer);
    meta.set("projection", to_string(j.mode));
    const RenderSettings rs = picture_from_meta(j, meta);
    SampleStoreSource source(*store, j.iso, j.sp);
    IsoSplatResult r;
    const std::size_t points = run_to_outputs(j.out(), j.png, meta, rs, j.threads, [&](const Stage* draw, Sink& sink) {
        return run_isosplat_sample_store(source, j.iso, j.mode, sink, {j.threads}, PipelineShape::two_stage, {nullptr, draw});
    }, r);
    if (j.stats) print_isosplat_stats(j.stats, path, j.iso, j.mode, r, points, j.threads, 1);
    return points;
}

void run_isosplat_mpi_job(const IsosplatJob& j, MpiSession& mpi, VolumeInput& in) {
    const MpiIsosurfaceResult m = run_isosplat_mpi(mpi, in, j.iso, j.mode, j.sp, j.threads, j.producer,
                                                   [&](const StreamMeta& meta, const std::function<void(Sink&)>& produce) {
                                                       const bool said = warn_if_iso_outside(j.iso, in.value_range(), in.path);
                                                       if (j.warned) *j.warned = said;
                                                       IsoSplatResult unused;
                                                       return run_to_outputs(j.out(), j.png, meta, picture_from_meta(j, meta), j.threads,
                                                                             [&](const Stage*, Sink& sink) {
                                                                                 produce(sink);
                                                                                 return IsoSplatResult{};
                                                                             }, unused, /*parallel_draw=*/false);
                                                   });
    if (m.root && j.stats) print_isosplat_stats(j.stats, m.path, j.iso, j.mode, m.result, m.points, j.threads, m.ranks);
}

}  // namespace meshless
