// meshless splat: software surface splatting of a point stream or PLY (section 3.6).
#include <chrono>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/render_output.hpp"
#include "formats/ply_points.hpp"
#include "kernels/errors.hpp"
#include "stream/point_sinks.hpp"
#include "stream/runner.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless::cli {

int cmd_splat(int argc, char** argv) {
    Args a("splat", "[INPUT|-] -o img.png [--kernel quad|ewa] [--turntable N] [camera options]",
           "Renders oriented points by surface splatting (software): quadrilateral (QSplat-style) or\n"
           "elliptical EWA kernels with depth-tested, normalised accumulation and Phong shading.\n"
           "INPUT is a point stream (stdin by default) or a .ply point set.");
    a.option("output", "o", "FILE", "PNG output (required)")
        .option("turntable", "", "N", "render N frames, 360/N degrees apart about the y axis, as FILE_000.png ...; reports time per frame");
    add_camera_options(a);
    a.epilog("example: meshless generate vol.raw --iso 100.5 | meshless project | meshless splat -o img.png --turntable 36\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string png = a.require("output");
    const Camera cam = camera_from(a);
    const SplatKernel kernel = kernel_from(a);
    const long long frames = a.get_int_or("turntable", 0);
    if (frames < 0 || frames > 3600) throw UsageError("--turntable: expected 1..3600 frames");
    const std::string input = a.positional().empty() ? "-" : a.positional()[0];

    std::vector<PointRecord> points;
    std::optional<std::array<Vec3, 2>> bounds;
    if (input.size() > 4 && input.substr(input.size() - 4) == ".ply") {
        points = read_ply_points(input).points;
    } else {
        InputFile in(input);
        StreamReader reader(in.f, in.name);
        if (reader.kind() != RecordKind::point)
            throw FormatError(in.name + ": holds unprojected samples; run 'meshless project' first");
        reader.read_meta();
        bounds = meta_bounds(reader.meta());
        StreamSource source(reader);
        CollectSink sink;
        run_pipeline(source, {}, sink, {1});
        points = std::move(sink.points);
    }
    if (frames > 0) {
        const auto t = render_turntable(points, bounds, cam, kernel, static_cast<int>(frames), png);
        std::fprintf(stderr, "splat: turntable of %d frames, %zu points, %dx%d %s: %.2f ms/frame (min %.2f, max %.2f)\n",
                     t.frames, points.size(), cam.width, cam.height, kernel == SplatKernel::quad ? "quad" : "ewa",
                     1e3 * t.mean_seconds, 1e3 * t.min_seconds, 1e3 * t.max_seconds);
    } else {
        const auto st = render_to_png(points, bounds, cam, kernel, png);
        if (stderr_is_tty())
            std::fprintf(stderr, "splat: %zu points, %.2f ms\n", points.size(), 1e3 * st.seconds);
    }
    return 0;
}

}  // namespace meshless::cli
