// meshless render: direct volume rendering by ray casting a field (dissertation section 6.6 /
// Figure 6.6: LOD fields volume rendered and differenced against the original; section 7.4: volume
// rendering of scattered data). Volumes and brick stores are sampled trilinearly (stores through the
// brick cache, within --memory); scattered points and multiblock grids through a meshless field
// (rbf-grid, mpu, global-rbf, or a fitted .mlf). Nothing is resampled onto a grid first.
// The recipe is stream/field_render.hpp (the field, its empty-space boxes, the frame, the picture);
// this file reads the options and picks the input and the transfer function; stream/render_outputs.hpp
// writes the picture and compares it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <exception>
#include <stdexcept>

#include "cli/commands.hpp"
#include "formats/point_set_reader.hpp"
#include "cli/common.hpp"
#include "cli/progress_meter.hpp"
#include "cli/errors.hpp"
#include "cli/field_cli.hpp"
#include "formats/atomic_file.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/png_reader.hpp"
#include "formats/png_writer.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "kernels/image_compare.hpp"
#include "kernels/ray_caster.hpp"
#include "ooc/brick_store.hpp"
#include "stream/field_render.hpp"
#include "stream/store_render.hpp"
#include "stream/render_outputs.hpp"

namespace meshless::cli {

namespace {

std::array<double, 3> parse_rgb(const std::string& s, const char* what) {
    double v[3];
    char tail;
    if (std::sscanf(s.c_str(), "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3)
        throw UsageError(std::string(what) + ": expected R,G,B in [0, 1], got '" + s + "'");
    for (double x : v)
        if (!(x >= 0 && x <= 1)) throw UsageError(std::string(what) + ": expected R,G,B in [0, 1], got '" + s + "'");
    return {v[0], v[1], v[2]};
}

/// The library's render input (stream/field_render.hpp) and the meshless field it may render, or
/// the point store it renders slab by slab (stream/store_render.hpp).
struct CliRenderInput {
    RenderInput in;
    BuiltField built;
    std::optional<StoreQueries> store;
    StoreQueryReport report;
};

CliRenderInput open_render_input(const Args& a) {
    CliRenderInput r;
    const auto& pos = a.positional();
    const std::string& first = pos[0];
    const bool store = is_brick_store(first) || ends_with_ci(first, ".mlb");
    // "-": a volume on standard input (open_volume_input spools it)
    // a .raw of float32 x,y,z,v records (no name convention, no --dims) is points, as isosurface reads it
    const bool raw_points = pos.size() == 1 && lower_extension(first) == ".raw" && !a.has("dims") && looks_like_point_set(first);
    const bool volume = store || (pos.size() == 1 && (first == "-" || (!looks_like_multiblock(first) && !raw_points &&
                                                                      looks_like_volume(first))));
    // scattered points: mpu, multiblock grids: rbf-grid, as isosurface and fit build (stream/field_data.hpp)
    const std::string data_default = data_field_default(pos);
    const std::string kind = a.get_or("field", volume ? "trilinear" : data_default);
    if (volume) {
        if (pos.size() > 1) throw UsageError("render takes one volume (got " + std::to_string(pos.size()) + " inputs)");
        if (kind != "trilinear")
            throw UsageError("--field " + kind + ": " + first +
                             " is a volume, rendered with --field trilinear (meshless sample makes scattered points of it)");
        // the meshless fields' and the point readers' options do nothing to a volume: say so
        for (const char* o : {"binning", "support", "local-points", "max-points", "alpha", "hardy-c", "hardy-c-world",
                              "normalise-axes", "columns", "value", "q", "q-component", "function", "allow-trailing", "strict",
                              "merge-blocks", "lod-level", "lod-error"})
            if (a.declared(o) && a.has(o))
                throw UsageError("--" + std::string(o) + " applies to point sets and multiblock grids; " + first +
                                 " is a volume, rendered through its trilinear interpolant");
        r.in = volume_render_input(open_volume_input(a, /*stream=*/false));
    } else {
        if (kind == "trilinear")
            throw UsageError("--field trilinear: " + first + " is not a volume; scattered points and multiblock grids render "
                             "through rbf-grid, mpu, global-rbf or a fitted .mlf");
        const bool store = queries_store_slabs(a, /*warn=*/false);  // (--memory to other points: refused below)
        for (const char* o : {"dims", "type", "spacing", "array", "memory", "crop"})
            if (a.declared(o) && a.has(o) && !(store && std::string(o) == "memory"))
                throw UsageError("--" + std::string(o) + " applies to volumes" +
                                 (std::string(o) == "memory"  ? std::string(" read from brick stores (.mlb) and to point stores (.mlc) with the mpu field")
                                  : std::string(o) == "array" ? std::string(" (.vti, .vtk, vtk.js)")
                                  : std::string(o) == "crop"  ? std::string()
                                                              : std::string(" (raw)")) +
                                 "; " + first + " is read as points");
        if (store) {
            r.store = open_store_queries(first);
            r.in = store_render_input(*r.store, first);
            return r;
        }
        const PointSet pts = read_field_points(pos, a);
        if (pts.size() == 0) throw FormatError(first + ": no points to render");
        r.built = build_field(a, pts, data_default);
        r.in = points_render_input(pts, *r.built.field, first);
    }
    return r;
}

TransferFunction transfer_function_arg(const Args& a, const std::array<double, 2>& data_range) {
    const std::string tf = a.get_or("tf", "grey");
    std::array<double, 2> range = data_range;
    if (auto r = a.get("range")) {
        const auto comma = r->find(',');
        if (comma == std::string::npos) throw UsageError("--range: expected LO,HI, got '" + *r + "'");
        range = {parse_finite(r->substr(0, comma), "--range"), parse_finite(r->substr(comma + 1), "--range")};
        if (!(range[0] < range[1])) throw UsageError("--range: LO must be less than HI, got '" + *r + "'");
    }
    return render_transfer_function(tf, range, a.has("range"));
}

/// render --help: what it draws and how.
constexpr const char* kRenderHelp =
           "Direct volume rendering by ray casting the field itself (dissertation section 6.6, Figure 6.6;\n"
           "section 7.4): front-to-back emission-absorption compositing with the opacity corrected for the\n"
           "step (a' = 1 - (1 - a)^(step / ref_step)), early ray termination, empty-space skipping from the\n"
           "field's value bounds, optional headlight shading from the field's gradient.\n"
           "INPUT: a volume (every format meshless reads) or a brick store (.mlb, read through the brick cache\n"
           "within --memory), sampled trilinearly (--field trilinear, the default and only field of a volume);\n"
           "or scattered points (a .raw of float32 x,y,z,v records included) / multiblock grids, sampled\n"
           "through a meshless field (--field rbf-grid | mpu | global-rbf | FILE.mlf; default mpu for points,\n"
           "rbf-grid for multiblock grids, the fields isosurface builds). Nothing is resampled onto a grid first.\n"
           "Transfer function (--tf): a preset spanning the data's value range (or --range LO,HI): grey,\n"
           "viridis, ct-bone, ct-skin; or a text file of rows 'value r g b a' sorted by value, components in\n"
           "[0, 1]. Opacities are per reference step = the default step: half the smallest voxel spacing\n"
           "(volumes) or half the mean point spacing (points); --step changes the sampling, not the opacity.\n"
           "--compare REF.png prints RMSE and PSNR of the picture against REF (PSNR 'inf' when identical) on\n"
           "stdout (stderr when -o - writes the picture there; a reference of another size than --size is refused\n"
           "before rendering) and --diff writes the difference picture (|a - b| x --diff-gain).\n"
           "The picture's bytes do not depend on --threads.";

void declare_render_options(Args& a) {
    a.option("output", "o", "FILE", "PNG output (required)")
        .option("tf", "", "PRESET|FILE", "transfer function: grey | viridis | ct-bone | ct-skin | FILE of 'value r g b a' rows", "grey")
        .option("range", "", "LO,HI", "presets: the value range they span (default: the data's)")
        .option("step", "", "S", "world units between samples along a ray, > 0 (default: half the data spacing)")
        .option("ref-step", "", "S", "the slab thickness the transfer function's opacities are for, > 0 (default: the default\n"
                                    "                            step); give two renderings the same to compare them (a LOD and its original)")
        .option("bounds", "", "X0,Y0,Z0,X1,Y1,Z1", "frame this box instead of the data's bounding box (the same frame\n"
                                                   "                            for a LOD and its original): fields of points are rendered over it,\n"
                                                   "                            volumes over the part their grid covers")
        .flag("shade", "headlight Phong shading with the field's gradient as the normal")
        .flag("no-skip", "evaluate every sample where there is data (no empty-space skipping; for comparison)")
        .option("background", "", "R,G,B", "background colour, components in [0, 1]", "0,0,0")
        .option("compare", "", "REF.png", "print RMSE and PSNR of the picture against REF.png")
        .option("diff", "", "FILE.png", "with --compare: write the difference picture")
        .option("diff-gain", "", "G", "--diff: multiply the differences by G, > 0", "1")
        .flag("colorbar", "draw the transfer function's legend: its colours from the top value to the bottom one, its\n"
                          "                            opacity as a grey strip beside them (white: opaque), titled with --array's name")
        .flag("axes", "draw the world axes (x red, y green, z blue) and a scale bar of a round world length (drawn by\n"
                      "                            default, labelled with the unit, when the volume's file states its length unit)")
        .flag("no-axes", "draw no axes or scale bar, even where the length unit is known");
    add_orbit_options(a, "512x512");
    add_field_options(a, /*with_coverage=*/false, kDataFieldDefaultHelp);  // --field ... --stats, point-set options, --threads
    a.option("dims", "", "X,Y,Z", "raw volumes: samples along x, y, z")
        .option("type", "", "T", "raw volumes: uint8 | int16 | uint16 | float32")
        .option("spacing", "", "SX,SY,SZ", "raw volumes: voxel spacing, world units, 0 < s <= 3.4e38", "1,1,1")
        .option("series", "", "UID|N", "DICOM: the series to read from a folder holding several (its UID, or N in their listing)");
    add_array_option(a);
    add_crop_option(a);
    a.option("memory", "", "BYTES",
             "brick stores (.mlb): the brick cache, e.g. 256M, 2G (default 256M); point stores (.mlc) with the mpu field: the "
             "budget the field's slabs along z are sized to (default: the memory this process may use); the picture does "
             "not depend on it")
        .validate([](const std::string& v) { (void)parse_memory_size(v); });
    add_quiet_option(a);
    a.positionals(1, 1000);
    a.epilog("examples: meshless render chest.vti --tf ct-bone --shade -o chest.png\n"
             "          meshless render points.ply --field mpu -o lod.png --compare chest.png --diff diff.png\n");
}

/// True when every pixel of `p` has the first pixel's colour (nothing drawn over the background).
bool uniform_picture(const Image& p) {
    for (std::size_t i = 3; i < p.rgb.size(); ++i)
        if (p.rgb[i] != p.rgb[i % 3]) return false;
    return true;
}

/// --bounds X0,Y0,Z0,X1,Y1,Z1 (stream/field_render.hpp render_frame), if given.
std::optional<std::array<Vec3, 2>> bounds_arg(const Args& a) {
    const auto b = a.get("bounds");
    if (!b) return std::nullopt;
    double v[6];
    char tail;
    if (std::sscanf(b->c_str(), "%lf,%lf,%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &tail) != 6)
        throw UsageError("--bounds: expected X0,Y0,Z0,X1,Y1,Z1, got '" + *b + "'");
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(v[i]) || !std::isfinite(v[i + 3]) || !(v[i] < v[i + 3]))
            throw UsageError("--bounds: expected finite X0 < X1, Y0 < Y1, Z0 < Z1, got '" + *b + "'");
    return std::array<Vec3, 2>{Vec3{v[0], v[1], v[2]}, Vec3{v[3], v[4], v[5]}};
}

}  // namespace

int cmd_render(int argc, char** argv) {
    Args a("render", "INPUT... -o img.png [--field KIND|FILE.mlf] [--tf PRESET|FILE] [camera options] [--compare REF.png]",
           kRenderHelp);
    declare_render_options(a);
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string png = require_output_extension(a.require("output"), ".png", "-o", "a PNG image");
    if (a.has("diff") && !a.has("compare")) throw UsageError("--diff needs --compare REF.png");
    const double gain = parse_finite(a.get_or("diff-gain", "1"), "--diff-gain");
    if (!(gain > 0)) throw UsageError("--diff-gain: must be positive");
    if (auto d = a.get("diff")) {
        require_output_extension(*d, ".png", "--diff", "a PNG image");
        if (*d == png) throw UsageError("-o and --diff name the same output '" + png + "'");
    }
    Camera cam = camera_from(a, "512x512");
    RenderOptions ro;
    ro.shade = a.has("shade");
    ro.no_skip = a.has("no-skip");
    ro.background = parse_rgb(a.get_or("background", "0,0,0"), "--background");
    if (auto s = a.get("step")) {
        ro.step = parse_finite(*s, "--step");
        if (!(*ro.step > 0)) throw UsageError("--step: must be positive");
    }
    ro.threads = threads(a);
    // the reference and the outputs before any work: a reference of another size, or an output
    // that cannot be created, fails at once and writes nothing
    std::optional<Image> ref;
    if (auto ref_path = a.get("compare")) {
        ref = read_png(*ref_path);
        if (ref->width != cam.width || ref->height != cam.height)
            throw FormatError(*ref_path + ": " + std::to_string(ref->width) + "x" + std::to_string(ref->height) +
                              " pixels, the rendering is " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                              " (--size)");
    }
    AtomicFile png_file(png);
    std::optional<AtomicFile> diff_file;
    if (auto d = a.get("diff")) diff_file.emplace(*d);

    CliRenderInput input = open_render_input(a);
    RenderInput& in = input.in;
    if (in.volume) apply_anatomical_default(a, *in.volume, cam);  // head up, face to the viewer, where the header says
    const TransferFunction tf = transfer_function_arg(a, in.range);
    if (auto r = a.get("ref-step")) {
        ro.ref_step = parse_finite(*r, "--ref-step");
        if (!(*ro.ref_step > 0)) throw UsageError("--ref-step: must be positive");
    }
    ro.bounds = bounds_arg(a);
    const bool tty = stderr_is_tty();
    // rays (pixels) as the tiles finish; the ray caster reports the finished fraction, serialised
    ProgressMeter meter = ProgressMeter::of(a, "rays", static_cast<double>(cam.width) * cam.height);
    const bool show = progress_wanted(a);
    auto progress = [&](double f) { meter.set_fraction(f); };
    const auto shown = show ? std::function<void(double)>(progress) : std::function<void(double)>();
    const RenderResult rr = input.store ? render_store_field(*input.store, store_query_params(a), in, cam, tf, ro, shown, &input.report)
                                        : render_field(in, cam, tf, ro, shown);
    meter.done();
    if (input.store && a.has("stats")) print_store_query_stats(stderr, "render", input.store->plan, input.report);
    // a point set whose picture is one colour (a PLY isosurface's points all carry the isovalue: a
    // constant field that the transfer function maps to nothing) says so instead of a silent black image
    if (!in.volume && uniform_picture(rr.picture))
        std::fprintf(stderr, "meshless render: warning: %s: the picture is all background (values %g .. %g; an isosurface's "
                             "points carry one value: splat them instead, meshless splat)\n",
                     terminal_safe(a.positional()[0]).c_str(), in.range[0], in.range[1]);
    RenderFiles files;
    files.png = &png_file;
    if (ref) files.reference = &*ref;
    if (diff_file) files.diff = &*diff_file;
    files.diff_gain = gain;
    if (a.has("colorbar")) files.legend = &tf;
    files.legend_title = a.get_or("array", "");
    files.axes = axes_choice(a);
    // the comparison on stdout, unless a picture goes there (-o - or --diff -)
    files.comparison = png == "-" || a.get_or("diff", "") == "-" ? stderr : stdout;
    if ((tty && !a.has("quiet")) || a.has("stats")) files.stats = stderr;
    write_render_files(in, cam, rr, ro.threads, files);
    return 0;
}

}  // namespace meshless::cli
