// meshless splat: software surface splatting of a point stream or PLY (section 3.6).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/render_output.hpp"
#include "formats/png_writer.hpp"
#include "kernels/errors.hpp"
#include "stream/ply_source.hpp"
#include "stream/point_spool.hpp"
#include "stream/project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/splat_sink.hpp"
#include "stream/stream_endpoints.hpp"
#include "stream/turntable.hpp"

namespace meshless::cli {

int cmd_splat(int argc, char** argv) {
    Args a("splat", "[INPUT|-] -o img.png [--kernel quad|ewa] [--turntable N] [camera options]",
           "Renders oriented points by surface splatting (software): quadrilateral (QSplat-style) or\n"
           "elliptical EWA kernels with depth-tested, normalised accumulation and Phong shading.\n"
           "INPUT is a point stream (stdin by default) or a .ply point set. Given a sample stream (from\n"
           "`meshless generate` or `meshless extract`), it projects at render time (paradigms B and D of\n"
           "Table 3.1): the isovalue comes from --iso or the stream. Points are drawn as they arrive (memory =\n"
           "the image buffers + one batch; the EWA kernel spools the points to an unlinked file in $TMPDIR\n"
           "for its second pass); the camera frames the surface bounds recorded in the stream or PLY.\n"
           "Input without recorded bounds, and --turntable, spool the points once to such a file (the\n"
           "frame is then known; each turntable frame replays the file): memory stays bounded.");
    a.option("output", "o", "FILE", "PNG output (required)")
        .option("iso", "", "V", "sample streams: isovalue to project onto (default: the stream's)")
        .option("projection", "", "MODE", "sample streams: approx | exact | none", "approx")
        .option("turntable", "", "N", "render N frames, 360/N degrees apart about the y axis, as FILE_000.png ...; reports time per frame")
        .flag("stats", "print the point count, time and throughput to stderr");
    add_camera_options(a);
    add_thread_option(a);
    a.epilog("example: meshless generate vol.raw --iso 100.5 | meshless project | meshless splat -o img.png --turntable 36\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string png = require_output_extension(a.require("output"), ".png", "-o", "a PNG image");
    const RenderSettings rs = render_settings(a);
    const Camera& cam = rs.camera;
    const long long frames = a.get_int_or("turntable", 0);
    if (a.has("turntable") && (frames < 1 || frames > 3600)) throw UsageError("--turntable: expected 1..3600 frames");
    if (frames > 0 && png == "-") throw UsageError("--turntable writes one file per frame: give -o NAME.png, not '-'");
    const std::string input = a.positional().empty() ? "-" : a.positional()[0];

    const int nthreads = threads(a);
    const bool is_ply = input.size() > 4 && input.substr(input.size() - 4) == ".ply";
    // The graph: PLY file or point/sample stream -> [project] -> draw (parallel) -> splat sink.
    std::unique_ptr<StreamReader> reader;
    std::optional<InputFile> in;
    std::optional<PointSpool> spool;  // see below; outlives the source that may replay it
    std::unique_ptr<Source> source;
    std::optional<std::array<Vec3, 2>> bounds;
    std::optional<ProjectStage> project;
    if (is_ply) {
        if (a.has("iso")) throw UsageError("--iso applies to sample streams; " + input + " holds projected points");
        auto ply = std::make_unique<PlySource>(input);
        bounds = ply_bounds(ply->comments());  // the surface bounds recorded by isosurface/write
        source = std::move(ply);
    } else {
        in.emplace(input);
        reader = std::make_unique<StreamReader>(in->f, in->name);
        reader->read_meta();
        bounds = meta_bounds(reader->meta());
        if (reader->kind() == RecordKind::seed)
            throw UsageError(in->name + ": holds unprojected multiblock seeds; project them first: meshless project --field KIND BLOCKS...");
        source = std::make_unique<StreamSource>(*reader);
        if (reader->kind() == RecordKind::sample) {
            // paradigms (B)/(D): projection at render time
            project.emplace(stream_iso(a, reader->meta()), parse_projection(a.get_or("projection", "approx")));
        } else if (a.has("iso")) {
            throw UsageError("--iso applies to sample streams; this stream holds projected points");
        }
    }
    std::vector<const Stage*> stages;
    if (project) stages.push_back(&*project);

    // A turntable draws every point once per frame, and a picture without recorded bounds needs all
    // the points before its first one is drawn: the points (projected) go once to a point spool,
    // which is then replayed; memory stays a few batches.
    if (frames > 0 || !bounds) {
        spool.emplace("splat-spool");
        run_pipeline(*source, stages, *spool, {nthreads});
        if (!bounds) bounds = spool->bounds();
        if (frames > 0) {
            const auto t = render_turntable(*spool, *bounds, cam, rs.kernel, rs.shading, static_cast<int>(frames), nthreads,
                                            [&](int i, const Image& img) { write_png(img, frame_path(png, i)); });
            std::fprintf(stderr, "splat: turntable of %d frames, %llu points, %dx%d %s: %.2f ms/frame (min %.2f, max %.2f)\n",
                         t.frames, static_cast<unsigned long long>(spool->size()), cam.width, cam.height,
                         rs.kernel == SplatKernel::quad ? "quad" : "ewa", 1e3 * t.mean_seconds, 1e3 * t.min_seconds,
                         1e3 * t.max_seconds);
            return 0;
        }
        source = std::make_unique<PointSpoolSource>(*spool);
        stages.clear();  // projected already
    }
    const auto t0 = std::chrono::steady_clock::now();
    SplatSink sink(cam, rs.kernel, rs.shading, *bounds, nthreads, spool ? &*spool : nullptr);
    stages.push_back(&sink.stage());
    run_pipeline(*source, stages, sink, {nthreads});
    write_png(sink.image(), png);
    if (stderr_is_tty() || a.has("stats"))
        std::fprintf(stderr, "splat: %llu points, %dx%d %s, %d thread(s): %.3f s (%.2f M points/s)\n",
                     static_cast<unsigned long long>(sink.points()), cam.width, cam.height,
                     rs.kernel == SplatKernel::quad ? "quad" : "ewa", nthreads,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                     1e-6 * sink.points() / std::max(1e-9, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
    return 0;
}

}  // namespace meshless::cli
