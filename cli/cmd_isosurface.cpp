// meshless isosurface: paradigm (C) iso-splatting in one process (dissertation chapter 3).
#include <chrono>
#include <cstdio>
#include <cstring>

#include "cli/commands.hpp"
#include "cli/mpi_session.hpp"
#include "formats/atomic_file.hpp"
#include "formats/png_writer.hpp"
#include "cli/common.hpp"
#include "cli/render_output.hpp"
#include "cli/sample_store_cli.hpp"
#include "formats/ply_points.hpp"
#include "kernels/errors.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"
#include "stream/project_stage.hpp"
#include "stream/sample_store_source.hpp"

namespace meshless::cli {

namespace {

/// Writes -o and --png as one outcome: the picture is rendered before anything is written, and
/// if writing the second file fails the first is removed, so a failed run leaves neither.
void write_outputs(const Args& a, const StreamMeta& meta, std::span<const PointRecord> points,
                   const RenderSettings& rs) {
    std::optional<Image> img;
    if (a.has("png")) img = render_splats(points, rs.camera, rs.kernel, rs.shading, nullptr, meta_bounds(meta));
    const auto out = a.get("output");
    if (out) write_ply_points(*out, points, ply_comments(meta));
    if (!img) return;
    try {
        write_png(*img, *a.get("png"));
    } catch (...) {
        if (out && *out != "-" && !is_streaming_output(*out)) std::remove(out->c_str());
        throw;
    }
}

void print_stats(const std::string& path, double iso, Projection mode, const IsoSplatResult& r, std::size_t points,
                 int nthreads, int ranks) {
    std::fprintf(stderr,
                 "isosurface: %s iso %g: %lld active cells, %zu points (%s projection; discarded: %lld too far, %lld flat, "
                 "%lld missed; %lld cells with NaN/Inf skipped), %.3f s on %d thread(s) x %d rank(s)\n",
                 path.c_str(), iso, static_cast<long long>(r.sampling.active_cells), points, to_string(mode),
                 static_cast<long long>(r.projection.too_far), static_cast<long long>(r.projection.flat),
                 static_cast<long long>(r.projection.missed), static_cast<long long>(r.sampling.nonfinite_cells), r.seconds,
                 nthreads, ranks);
}

/// mpirun -np N: each rank iso-splats a contiguous Morton range of the active bricks; rank 0
/// gathers the points in rank order (= the single-process order) and writes the outputs.
int isosurface_mpi(const Args& a, int argc, char** argv, double iso, Projection mode, const SamplingParams& sp,
                   const RenderSettings& rs, int nthreads) {
    MpiSession mpi(&argc, &argv);
    try {
        VolumeInput in = open_volume_input(a);
        if (!in.store)
            throw UsageError("MPI runs need a brick store (.mlb): meshless convert " + in.path + " -o vol.mlb");
        if (mpi.rank() == 0) warn_if_iso_outside(iso, in.value_range(), in.path);
        const std::vector<std::size_t> active = in.index->active(iso);
        const std::size_t n = active.size(), r0 = n * mpi.rank() / mpi.size(), r1 = n * (mpi.rank() + 1) / mpi.size();
        CollectSink sink;
        IsoSplatResult r = run_isosplat_bricks(*in.store, *in.cache, {active.begin() + r0, active.begin() + r1}, iso, mode,
                                               sp, sink, {nthreads});
        const std::vector<std::byte> all = mpi.gather_to_root(sink.points.data(), sink.points.size() * sizeof(PointRecord));
        const auto sums = mpi.sum_to_root({r.sampling.active_cells, r.sampling.nonfinite_cells, r.projection.too_far,
                                           r.projection.flat, r.projection.missed});
        if (mpi.rank() != 0) return 0;
        std::vector<PointRecord> points(all.size() / sizeof(PointRecord));
        std::memcpy(points.data(), all.data(), all.size());
        StreamMeta meta = volume_meta(in, iso, a.command_line());
        meta.set("projection", to_string(mode));
        write_outputs(a, meta, points, rs);
        r.sampling = {sums[0], sums[1]};
        r.projection.too_far = sums[2];
        r.projection.flat = sums[3];
        r.projection.missed = sums[4];
        if (a.has("stats")) print_stats(in.path, iso, mode, r, points.size(), nthreads, mpi.size());
        return 0;
    } catch (const BrokenPipe&) {
        return 0;
    } catch (const std::exception& e) {
        // one failing rank ends the job: nothing is renamed into place, every rank exits non-zero
        std::fprintf(stderr, "meshless isosurface (rank %d of %d): %s\n", mpi.rank(), mpi.size(), e.what());
        mpi.abort(dynamic_cast<const UsageError*>(&e) ? 1 : (dynamic_cast<const FormatError*>(&e) || dynamic_cast<const IoError*>(&e)) ? 2 : 3);
    }
}

/// A sample store (.mls) input: paradigm (A) in one process (section 3.5, Table 3.1): the store's
/// candidate rows, recomputed from its .mlb, projected; the same points as from the .mlb.
int isosurface_sample_store(const Args& a, double iso, Projection mode, const SamplingParams& sp,
                            const RenderSettings& rs, int nthreads) {
    const std::string path = a.positional()[0];
    const auto store = SampleStore::open(path);
    warn_if_iso_outside(iso, {store->info().value_lo, store->info().value_hi}, path);
    StreamMeta meta = sample_store_meta(*store, iso, a.command_line());
    meta.set("projection", to_string(mode));
    const auto t0 = std::chrono::steady_clock::now();
    SampleStoreSource source(*store, iso, sp);
    const ProjectStage project(iso, mode);
    const Stage* stages[] = {&project};
    IsoSplatResult r;
    std::size_t points = 0;
    if (a.has("png")) {
        CollectSink sink;
        run_pipeline(source, stages, sink, {nthreads});
        points = sink.points.size();
        write_outputs(a, meta, sink.points, rs);
    } else {
        PlySink sink(*a.get("output"), ply_comments(meta));
        run_pipeline(source, stages, sink, {nthreads});
        points = sink.count();
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.sampling.active_cells = static_cast<std::int64_t>(source.emitted());
    r.projection = project.stats();
    if (a.has("stats")) print_stats(path, iso, mode, r, points, nthreads, 1);
    return 0;
}

}  // namespace

int cmd_isosurface(int argc, char** argv) {
    Args a("isosurface", "VOLUME --iso V -o out.ply [--png out.png] [options]",
           "Paradigm (C) iso-splatting: one sample per active cell (cell centre), value and gradient by\n"
           "trilinear interpolation, projected onto the isosurface; writes an oriented point set\n"
           "(binary PLY: x y z nx ny nz radius value) and/or a surface-splatted picture.\n"
           "VOLUME: raw (name_XxYxZ_type.raw or --dims/--type), NRRD (.nrrd/.nhdr), MetaImage (.mhd/.mha),\n"
           "VTK legacy (.vtk), VTK XML image (.vti), vtk-js (index.json), SLC, NIfTI, or a brick store (.mlb,\n"
           "see meshless convert), read brick by brick: only bricks the isosurface crosses, within --memory,\n"
           "or a paradigm (A) sample store (.mls, see meshless generate --all): only its candidate cell rows.");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "point set output (.ply, '-' for stdout)")
        .option("png", "", "FILE", "also render the points to this PNG")
        .option("projection", "", "MODE", "approx (one Newton step, Eq. 3.5) | exact (ray-trilinear cubic, Eq. 3.3) | none", "approx")
        .flag("stats", "print counts (active cells, discarded samples) and timing to stderr");
    add_sampling_options(a);
    add_volume_options(a);
    add_memory_option(a);
    add_thread_option(a);
    add_camera_options(a);
    a.epilog("examples: meshless isosurface ../shared/data/fuel/fuel_64x64x64_uint8.raw --iso 20.5 -o fuel.ply --png fuel.png\n"
             "          meshless isosurface vol.mlb --iso 100.5 --memory 256M -o out.ply\n"
             "          mpirun -np 4 meshless isosurface vol.mlb --iso 100.5 -o out.ply   (ranks split the active bricks)\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = parse_finite(a.require("iso"), "--iso");
    const auto out = a.get("output");
    const auto png = a.get("png");
    if (!out && !png) throw UsageError("nothing to write: give -o FILE and/or --png FILE");
    if (out && png && *out == *png && (*out == "-" || !is_streaming_output(*out)))
        throw UsageError("-o and --png name the same output '" + *out + "'");
    const Projection mode = parse_projection(a.get_or("projection", "approx"));
    const SamplingParams sp = sampling_params(a);
    const RenderSettings rs = render_settings(a);
    const int nthreads = threads(a);

    if (launched_world_size() > 1) return isosurface_mpi(a, argc, argv, iso, mode, sp, rs, nthreads);
    if (!a.positional().empty() && is_sample_store(a.positional()[0]))
        return isosurface_sample_store(a, iso, mode, sp, rs, nthreads);

    VolumeInput in = open_volume_input(a);
    warn_if_iso_outside(iso, in.value_range(), in.path);
    StreamMeta meta = volume_meta(in, iso, a.command_line());
    meta.set("projection", to_string(mode));

    IsoSplatResult r;
    std::size_t points = 0;
    if (png) {
        CollectSink sink;
        r = run_isosplat_input(in, iso, mode, sp, sink, nthreads, PipelineShape::fused);
        points = sink.points.size();
        write_outputs(a, meta, sink.points, rs);
    } else {
        PlySink sink(*out, ply_comments(meta));
        r = run_isosplat_input(in, iso, mode, sp, sink, nthreads, PipelineShape::fused);
        points = sink.count();
    }
    if (a.has("stats")) print_stats(in.path, iso, mode, r, points, nthreads, 1);
    return 0;
}

}  // namespace meshless::cli
