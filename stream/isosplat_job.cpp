#include "stream/isosplat_job.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "kernels/errors.hpp"
#include "ooc/sample_store.hpp"
#include "stream/color_by_stage.hpp"
#include "stream/continued_sink.hpp"
#include "stream/iso_range_warning.hpp"
#include "stream/sample_store_source.hpp"
#include "stream/stream_metadata.hpp"

namespace meshless {

namespace {

/// The picture of points whose metadata records their volume: its patient axes for the default
/// camera and, without a given range, its value range for the value colours — what splat of the
/// same points' PLY or stream draws.
/// The isovalues of a job in order: its `isos`, or `iso` alone.
std::vector<double> isovalues_of(const IsosplatJob& j) { return j.isos.empty() ? std::vector<double>{j.iso} : j.isos; }

/// The --stats line of each isovalue (one isovalue: the points written).
void print_each_isovalue(const IsosplatJob& j, const std::string& path, const std::vector<double>& isos,
                         const std::vector<IsoSplatResult>& r, const std::vector<std::size_t>& counts, std::size_t points) {
    for (std::size_t i = 0; i < isos.size(); ++i)
        print_isosplat_stats(j.stats, path, isos[i], j.mode, r[i], isos.size() > 1 ? counts[i] : points, j.threads, 1);
}

/// --color-by: the stage that gives each point the other array's value, with the array's name and
/// value range in the metadata and (unless given) the picture's colour range; nullopt without it.
std::optional<ColorByStage> color_by_stage(const IsosplatJob& j, const VolumeInput& in, StreamMeta& meta, RenderSettings& rs) {
    if (!j.color_by) return std::nullopt;
    const Volume& c = j.color_by->volume;
    if (!(c.grid == in.grid()))
        throw InvalidArgument("--color-by " + j.color_by->name + ": its grid differs from the volume's (" + in.path + ")");
    const std::array<double, 2> range = value_range(c.view());
    meta.set("value_name", j.color_by->name);
    meta.set("value_min", range[0]);
    meta.set("value_max", range[1]);
    if (!j.range_given) {
        rs.shading.value_lo = range[0];
        rs.shading.value_hi = range[1];
    }
    rs.legend_title = j.color_by->name;
    return std::optional<ColorByStage>(std::in_place, c.view());
}

/// The sample-store and MPI jobs: --color-by needs the volume's arrays.
void refuse_color_by(const IsosplatJob& j, const char* where) {
    if (j.color_by) throw InvalidArgument("--color-by " + j.color_by->name + ": " + where + " (give the volume itself)");
}

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
    const std::vector<double> isos = isovalues_of(j);
    RenderSettings rs = j.rs;
    // head up, face to the viewer, where the header says
    if (j.png && !j.up_given && in.frame && j.anatomical_camera) j.anatomical_camera(*in.frame, rs.camera);
    if (j.png && !j.up_given && !in.frame && j.no_axes_hint) j.no_axes_hint(in.path);
    StreamMeta meta = volume_meta(in, isos[0], j.producer);  // value range and surface bounds, one pass
    set_isovalues(meta, isos, [&](double v) { return surface_bounds(in, v); });
    if (!j.range_given) {
        rs.shading.value_lo = meta.get_double("value_min").value_or(j.iso);
        rs.shading.value_hi = meta.get_double("value_max").value_or(j.iso);
    }
    bool said = false;
    for (double v : isos)
        said = warn_if_iso_outside(v, {meta.get_double("value_min").value_or(NAN), meta.get_double("value_max").value_or(NAN)}, in.path,
                                   stderr, isos.size() > 1) || said;
    if (j.warned) *j.warned = said;
    meta.set("projection", to_string(j.mode));
    const std::optional<ColorByStage> recolour = color_by_stage(j, in, meta, rs);
    std::vector<IsoSplatResult> r;
    std::vector<std::size_t> counts;
    std::size_t points = 0;
    {  // (the progress display goes before the statistics)
        double work = 0;
        for (double v : isos) work += isosurface_work(in, v);
        const auto counted = j.progress ? j.progress("cell rows", work) : std::function<void(double)>();
        const ProgressStage progress([&](double n) { if (counted) counted(n); }, work_units);
        IsoSplatResult unused;
        points = run_to_outputs(j.out(), j.png, meta, rs, j.threads, [&](const Stage* draw, Sink& sink) {
            return run_each_isovalue(isos.size(), sink, r, counts, [&](std::size_t i, Sink& one) {
                return run_isosplat_input(in, isos[i], j.mode, j.sp, one, j.threads, PipelineShape::fused,
                                          {&progress, draw, recolour ? &*recolour : nullptr});
            });
        }, unused);
    }
    if (j.stats) print_each_isovalue(j, in.path, isos, r, counts, points);
    return points;
}

std::size_t run_isosplat_sample_store_job(const IsosplatJob& j, const std::string& path) {
    refuse_color_by(j, "a sample store holds one array");
    const std::vector<double> isos = isovalues_of(j);
    const auto store = SampleStore::open(path);
    bool said = false;
    for (double v : isos) said = warn_if_iso_outside(v, {store->info().value_lo, store->info().value_hi}, path, stderr, isos.size() > 1) || said;
    if (j.warned) *j.warned = said;
    StreamMeta meta = sample_store_meta(*store, isos[0], j.producer);
    set_isovalues(meta, isos, [&](double v) { return meta_bounds(sample_store_meta(*store, v, j.producer)); });
    meta.set("projection", to_string(j.mode));
    const RenderSettings rs = picture_from_meta(j, meta);
    std::vector<IsoSplatResult> r;
    std::vector<std::size_t> counts;
    IsoSplatResult unused;
    const std::size_t points = run_to_outputs(j.out(), j.png, meta, rs, j.threads, [&](const Stage* draw, Sink& sink) {
        return run_each_isovalue(isos.size(), sink, r, counts, [&](std::size_t i, Sink& one) {
            SampleStoreSource source(*store, isos[i], j.sp);
            return run_isosplat_sample_store(source, isos[i], j.mode, one, {j.threads}, PipelineShape::two_stage, {nullptr, draw});
        });
    }, unused);
    if (j.stats) print_each_isovalue(j, path, isos, r, counts, points);
    return points;
}

void run_isosplat_mpi_job(const IsosplatJob& j, MpiSession& mpi, VolumeInput& in) {
    refuse_color_by(j, "runs in one process, not under mpirun");
    if (j.isos.size() > 1) throw InvalidArgument("--iso: several isovalues run in one process; under mpirun give one isovalue per run");
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
