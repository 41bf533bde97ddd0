// meshless isosurface: paradigm (C) iso-splatting in one process (dissertation chapter 3).
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/render_output.hpp"
#include "formats/ply_points.hpp"
#include "kernels/errors.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"

namespace meshless::cli {

int cmd_isosurface(int argc, char** argv) {
    Args a("isosurface", "VOLUME --iso V -o out.ply [--png out.png] [options]",
           "Paradigm (C) iso-splatting: one sample per active cell (cell centre), value and gradient by\n"
           "trilinear interpolation, projected onto the isosurface; writes an oriented point set\n"
           "(binary PLY: x y z nx ny nz radius value) and/or a surface-splatted picture.\n"
           "VOLUME: raw (name_XxYxZ_type.raw or --dims/--type), NRRD (.nrrd/.nhdr), MetaImage (.mhd/.mha),\n"
           "VTK legacy (.vtk), VTK XML image (.vti), vtk-js (index.json), SLC, NIfTI.");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "point set output (.ply, '-' for stdout)")
        .option("png", "", "FILE", "also render the points to this PNG")
        .option("projection", "", "MODE", "approx (one Newton step, Eq. 3.5) | exact (ray-trilinear cubic, Eq. 3.3) | none", "approx")
        .flag("stats", "print counts (active cells, discarded samples) and timing to stderr");
    add_sampling_options(a);
    add_volume_options(a);
    add_thread_option(a);
    add_camera_options(a);
    a.epilog("example: meshless isosurface ../shared/data/fuel/fuel_64x64x64_uint8.raw --iso 20.5 -o fuel.ply --png fuel.png\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = parse_double(a.require("iso"), "--iso");
    const auto out = a.get("output");
    const auto png = a.get("png");
    if (!out && !png) throw UsageError("isosurface: nothing to write: give -o FILE and/or --png FILE");
    const Projection mode = parse_projection(a.get_or("projection", "approx"));
    const SamplingParams sp = sampling_params(a);
    const Camera cam = camera_from(a);
    const SplatKernel kernel = kernel_from(a);
    const int nthreads = threads(a);

    const std::string path = a.positional()[0];
    const Volume vol = load_volume(a);
    warn_if_iso_outside(iso, vol.value_range(), path);
    StreamMeta meta = volume_meta(path, vol, iso, a.command_line());
    meta.set("projection", to_string(mode));

    IsoSplatResult r;
    std::size_t points = 0;
    if (png) {
        CollectSink sink;
        r = run_isosplat(vol.view(), iso, mode, sp, sink, {nthreads});
        points = sink.points.size();
        if (out) write_ply_points(*out, sink.points, ply_comments(meta));
        render_to_png(sink.points, meta_bounds(meta), cam, kernel, *png);
    } else {
        PlySink sink(*out, ply_comments(meta));
        r = run_isosplat(vol.view(), iso, mode, sp, sink, {nthreads});
        points = sink.count();
    }
    if (a.has("stats"))
        std::fprintf(stderr,
                     "isosurface: %s iso %g: %lld active cells, %zu points (%s projection; discarded: %lld too far, %lld flat, "
                     "%lld missed; %lld cells with NaN/Inf skipped), %.3f s on %d thread(s)\n",
                     path.c_str(), iso, static_cast<long long>(r.sampling.active_cells), points, to_string(mode),
                     static_cast<long long>(r.projection.too_far), static_cast<long long>(r.projection.flat),
                     static_cast<long long>(r.projection.missed), static_cast<long long>(r.sampling.nonfinite_cells),
                     r.seconds, nthreads);
    return 0;
}

}  // namespace meshless::cli
