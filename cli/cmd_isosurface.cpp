// meshless isosurface: paradigm (C) iso-splatting in one process (dissertation chapter 3).
#include <cstdio>
#include <cstring>
#include <functional>

#include "cli/commands.hpp"
#include "cli/isosurface_mpi.hpp"
#include "cli/mpi_session.hpp"
#include "formats/atomic_file.hpp"
#include "formats/png_writer.hpp"
#include "cli/common.hpp"
#include "cli/render_output.hpp"
#include "formats/ply_points.hpp"
#include "kernels/errors.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"

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

/// The command's outputs around a graph run: -o alone streams into a PlySink; --png collects the
/// points, renders, then writes both (write_outputs). Shared by the single-process and MPI paths.
std::size_t write_isosurface(const Args& a, const StreamMeta& meta, const RenderSettings& rs,
                             const std::function<void(Sink&)>& produce) {
    if (a.has("png")) {
        CollectSink sink;
        produce(sink);
        write_outputs(a, meta, sink.points, rs);
        return sink.points.size();
    }
    PlySink sink(*a.get("output"), ply_comments(meta));
    produce(sink);
    return sink.count();
}

}  // namespace

int cmd_isosurface(int argc, char** argv) {
    Args a("isosurface", "VOLUME --iso V -o out.ply [--png out.png] [options]",
           "Paradigm (C) iso-splatting: one sample per active cell (cell centre), value and gradient by\n"
           "trilinear interpolation, projected onto the isosurface; writes an oriented point set\n"
           "(binary PLY: x y z nx ny nz radius value) and/or a surface-splatted picture.\n"
           "VOLUME: raw (name_XxYxZ_type.raw or --dims/--type), NRRD (.nrrd/.nhdr), MetaImage (.mhd/.mha),\n"
           "VTK legacy (.vtk), VTK XML image (.vti), vtk-js (index.json), SLC, NIfTI, or a brick store (.mlb,\n"
           "see meshless convert), read brick by brick: only bricks the isosurface crosses, within --memory.");
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

    if (launched_world_size() > 1) {
        const MpiIsosurfaceResult m = isosurface_mpi(a, argc, argv, iso, mode, sp, nthreads,
                                                     [&](const StreamMeta& meta, const std::function<void(Sink&)>& produce) {
                                                         return write_isosurface(a, meta, rs, produce);
                                                     });
        if (m.root && a.has("stats")) print_stats(m.path, iso, mode, m.result, m.points, nthreads, m.ranks);
        return 0;
    }

    VolumeInput in = open_volume_input(a);
    warn_if_iso_outside(iso, in.value_range(), in.path);
    StreamMeta meta = volume_meta(in, iso, a.command_line());
    meta.set("projection", to_string(mode));

    IsoSplatResult r;
    const std::size_t points = write_isosurface(a, meta, rs, [&](Sink& sink) {
        r = run_isosplat_input(in, iso, mode, sp, sink, nthreads, PipelineShape::fused);
    });
    if (a.has("stats")) print_stats(in.path, iso, mode, r, points, nthreads, 1);
    return 0;
}

}  // namespace meshless::cli
