// meshless splat: software surface splatting of a point stream or PLY (section 3.6).
#include <algorithm>
#include <cstdio>
#include <optional>
#include <utility>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/progress_meter.hpp"
#include "formats/binary_file.hpp"
#include "stream/splat_picture.hpp"

namespace meshless::cli {

/// splat --help: what it draws and how.
constexpr const char* kSplatHelp =
           "Renders oriented points by surface splatting (software): quadrilateral (QSplat-style) or\n"
           "elliptical EWA kernels with depth-tested, normalised accumulation and Phong shading.\n"
           "INPUT is a point stream (stdin by default), a .ply point set or a .vtp of oriented points (Normals,\n"
           "radius and value point arrays, as isosurface -o points.vtp writes them; read whole, 32 bytes a\n"
           "point). Given a sample stream (from\n"
           "`meshless generate` or `meshless extract`), it projects at render time (paradigms B and D of\n"
           "Table 3.1): the isovalue comes from --iso or the stream. Points are drawn as they arrive (memory =\n"
           "the image buffers + one batch; the EWA kernel spools the points to an unlinked file in $TMPDIR\n"
           "for its second pass); the camera frames the surface bounds recorded in the stream or PLY.\n"
           "Input without recorded bounds, and --turntable, spool the points once to such a file (the\n"
           "frame is then known; each turntable frame replays the file): memory stays bounded. A binary\n"
           "PLY of the points `isosurface` writes is not copied: it is read in place, once to frame and\n"
           "colour the picture, then by each drawing pass (or turntable frame).\n"
           "Colours (--color): value, block (multiblock points' block ids), normal or none, lit by the\n"
           "headlight; by default value when the points' values vary and the input does not record an\n"
           "isovalue (an isosurface's points all carry it), else none (the uniform surface colour). Colouring\n"
           "by value without --range, by default, or by block from a stream first spools the points (their\n"
           "value range, block ids). --colorbar draws the value range as a legend bar (or the block colours\n"
           "with their ids) into the picture.\n"
           "A .ply with faces (a triangle mesh, `meshless mc`) is drawn as its triangles instead: z-buffered,\n"
           "the vertex normals interpolated (perspective-correct) and lit as the splats are, the camera\n"
           "framing the mesh's bounds; --kernel is ignored, --color takes none (default), normal or block\n"
           "(the faces' block ids; a mesh has no values for --color value); single-threaded.";

int cmd_splat(int argc, char** argv) {
    Args a("splat", "[INPUT.ply|INPUT.vtp|-|MESH.ply] -o img.png [--kernel quad|ewa] [--turntable N] [camera options]",
           kSplatHelp);
    a.option("output", "o", "FILE", "PNG output (required)")
        .option("iso", "", "V", "sample streams: isovalue to project onto (default: the stream's)")
        .option("projection", "", "MODE", "sample streams: approx | exact | none", "approx")
        .option("turntable", "", "N", "render N frames (1..3600), 360/N degrees apart about the up axis (--up; y by default), as FILE_000.png ...; reports time per frame")
        .flag("stats", "print the point count, time and throughput to stderr");
    add_camera_options(a);
    add_color_options(a);
    add_thread_option(a);
    add_quiet_option(a);
    a.epilog("example: meshless generate vol.raw --iso 100.5 | meshless project | meshless splat -o img.png --turntable 36\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string png = require_output_extension(a.require("output"), ".png", "-o", "a PNG image");
    RenderSettings rs = render_settings(a);
    const ColorChoice cc = color_choice(a);
    const long long frames = a.get_int_or("turntable", 0);
    if (a.has("turntable") && (frames < 1 || frames > 3600)) throw UsageError("--turntable: expected 1..3600 frames");
    if (frames > 0 && png == "-") throw UsageError("--turntable writes one file per frame: give -o NAME.png, not '-'");
    const std::string input = a.positional().empty() ? "-" : a.positional()[0];
    if (input != "-") require_regular_file(input);  // a FIFO would block the open: pipes come as -
    SplatRequest r;
    r.input = input;
    r.png = png;
    r.frames = frames;
    r.threads = threads(a);
    r.color = cc;
    r.iso_given = a.has("iso");
    r.sample_projection = [&a](const StreamMeta& m) {
        const double iso = stream_iso(a, m);
        return std::pair(iso, parse_projection(a.get_or("projection", "approx")));
    };
    r.anatomical_camera = [&a](const AnatomicalFrame& f, Camera& c) { apply_anatomical_frame(a, f, c); };
    r.warn = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    std::optional<ProgressMeter> meter;
    if (frames > 0) {
        meter.emplace("meshless " + a.command(), "frames", static_cast<double>(frames), progress_wanted(a), progress_delay());
        r.frame_written = [&meter] { meter->add(1); };
    }
    const SplatReport rep = splat_picture(rs, r);
    if (meter) meter->done();
    if (rep.frames > 0 || stderr_is_tty() || a.has("stats")) print_splat_report(stderr, rep, rs.kernel, r.threads);
    return 0;
}

}  // namespace meshless::cli
