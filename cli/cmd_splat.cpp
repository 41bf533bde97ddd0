// meshless splat: software surface splatting of a point stream or PLY (section 3.6).
#include <chrono>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/render_output.hpp"
#include "formats/ply_points.hpp"
#include "kernels/errors.hpp"
#include "stream/point_sinks.hpp"
#include "stream/project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless::cli {

int cmd_splat(int argc, char** argv) {
    Args a("splat", "[INPUT|-] -o img.png [--kernel quad|ewa] [--turntable N] [camera options]",
           "Renders oriented points by surface splatting (software): quadrilateral (QSplat-style) or\n"
           "elliptical EWA kernels with depth-tested, normalised accumulation and Phong shading.\n"
           "INPUT is a point stream (stdin by default) or a .ply point set. Given a sample stream (from\n"
           "`meshless generate` or `meshless extract`), it projects at render time (paradigms B and D of\n"
           "Table 3.1): the isovalue comes from --iso or the stream.");
    a.option("output", "o", "FILE", "PNG output (required)")
        .option("iso", "", "V", "sample streams: isovalue to project onto (default: the stream's)")
        .option("projection", "", "MODE", "sample streams: approx | exact | none", "approx")
        .option("turntable", "", "N", "render N frames, 360/N degrees apart about the y axis, as FILE_000.png ...; reports time per frame");
    add_camera_options(a);
    a.epilog("example: meshless generate vol.raw --iso 100.5 | meshless project | meshless splat -o img.png --turntable 36\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string png = a.require("output");
    const RenderSettings rs = render_settings(a);
    const Camera& cam = rs.camera;
    const long long frames = a.get_int_or("turntable", 0);
    if (a.has("turntable") && (frames < 1 || frames > 3600)) throw UsageError("--turntable: expected 1..3600 frames");
    if (frames > 0 && png == "-") throw UsageError("--turntable writes one file per frame: give -o NAME.png, not '-'");
    const std::string input = a.positional().empty() ? "-" : a.positional()[0];

    std::vector<PointRecord> points;
    std::optional<std::array<Vec3, 2>> bounds;
    if (input.size() > 4 && input.substr(input.size() - 4) == ".ply") {
        PlyPoints ply = read_ply_points(input);
        points = std::move(ply.points);
        bounds = ply_bounds(ply.comments);  // the volume's bounds, so framing matches isosurface --png
    } else {
        InputFile in(input);
        StreamReader reader(in.f, in.name);
        reader.read_meta();
        bounds = meta_bounds(reader.meta());
        StreamSource source(reader);
        CollectSink sink;
        if (reader.kind() == RecordKind::sample) {
            // paradigms (B)/(D): projection at render time
            ProjectStage project(stream_iso(a, reader.meta()), parse_projection(a.get_or("projection", "approx")));
            const Stage* stages[] = {&project};
            run_pipeline(source, stages, sink, {1});
        } else {
            if (a.has("iso")) throw UsageError("--iso applies to sample streams; this stream holds projected points");
            run_pipeline(source, {}, sink, {1});
        }
        points = std::move(sink.points);
    }
    if (frames > 0) {
        const auto t = render_turntable(points, bounds, rs, static_cast<int>(frames), png);
        std::fprintf(stderr, "splat: turntable of %d frames, %zu points, %dx%d %s: %.2f ms/frame (min %.2f, max %.2f)\n",
                     t.frames, points.size(), cam.width, cam.height, rs.kernel == SplatKernel::quad ? "quad" : "ewa",
                     1e3 * t.mean_seconds, 1e3 * t.min_seconds, 1e3 * t.max_seconds);
    } else {
        const auto st = render_to_png(points, bounds, rs, png);
        if (stderr_is_tty())
            std::fprintf(stderr, "splat: %zu points, %.2f ms\n", points.size(), 1e3 * st.seconds);
    }
    return 0;
}

}  // namespace meshless::cli
