// Looking at scattered data directly through meshless fields (dissertation chapters 4-5, 7):
//   meshless probe POINTS --at x,y,z ...        value and gradient at given positions (CSV)
//   meshless slice POINTS --plane z=0.5 -o s.png colour-mapped slice with the nearby points overlaid
//   meshless resample POINTS --grid X,Y,Z -o v.nrrd   the field on a regular grid
// Each is a graph: a source of query positions -> FieldEvaluateStage -> a CSV / image / NRRD sink.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli/commands.hpp"
#include "formats/binary_file.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/field_cli.hpp"
#include "cli/progress_meter.hpp"
#include "stream/progress_stage.hpp"
#include "formats/atomic_file.hpp"
#include "formats/nrrd_writer.hpp"
#include "formats/png_writer.hpp"
#include "formats/text_header.hpp"
#include "kernels/colorbar.hpp"
#include "kernels/colormap.hpp"
#include "kernels/errors.hpp"
#include "stream/field_evaluate_stage.hpp"
#include "stream/field_query_sources.hpp"
#include "stream/field_sinks.hpp"
#include "stream/runner.hpp"

namespace meshless::cli {

namespace {

/// --stats: how many positions lay outside the data and how many values were kept within its range.
/// Without --stats, a warning when more than a tenth of the values inside the data had to be
/// clamped (under --extrapolate nan, where no value outside is clamped): the field overshoots its data there (sparse or noisy values), and the picture's flat
/// areas at the range's ends are the clamp's, not the data's. `total`: the positions evaluated.
void report_support(const Args& a, const BuiltField& f, const FieldEvaluateStage& e, std::size_t total) {
    if (!f.coverage) return;
    static constexpr const char* kModes[] = {"NaN", "clamped", "the nearest data value"};
    if (a.has("stats"))
        std::fprintf(stderr, "%s: %zu positions outside the data (%s), %zu values kept within the data range\n",
                     a.command().c_str(), e.uncovered(), kModes[static_cast<int>(f.extrapolate)], e.clamped());
    // (under --extrapolate nan, the default, only positions inside the data are clamped)
    const std::size_t inside = total - std::min(total, e.uncovered());
    if (f.extrapolate == Extrapolate::nan && inside > 0 && 10 * e.clamped() > inside)
        std::fprintf(stderr,
                     "meshless %s: warning: %zu of the %zu values inside the data (%.0f %%) lay outside its value range "
                     "and were clamped to it: the field overshoots its data there\n",
                     a.command().c_str(), e.clamped(), inside, 100.0 * static_cast<double>(e.clamped()) / static_cast<double>(inside));
}

/// Positions from a CSV/whitespace file ("-": standard input): three numbers per line; blank lines
/// and # comments skipped, an optional header line first; no position at all is a FormatError.
std::vector<Vec3> read_positions(const std::string& path) {
    std::error_code ec;
    if (path != "-" && std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a file of positions");
    std::ifstream file;
    if (path != "-") {
        require_regular_file(path);
        file.open(path);
        if (!file) throw IoError(path + ": cannot open");
    }
    std::istream& in = path == "-" ? std::cin : file;
    std::vector<Vec3> out;
    std::string line;
    bool first_line = true;
    for (std::size_t n = 1; std::getline(in, line); ++n) {
        for (char& c : line)
            if (c == ',' || c == ';' || c == '\t') c = ' ';
        std::istringstream ls(line);
        std::string first;
        if (!(ls >> first) || first[0] == '#') continue;
        double v[3];
        std::istringstream all(line);
        if (!(all >> v[0] >> v[1] >> v[2])) {
            // a header: the first line (comments and blank lines aside) when it does not start
            // with a number ("x,y,z")
            double num;
            std::istringstream head(first);
            if (first_line && !(head >> num)) {
                first_line = false;
                continue;
            }
            throw FormatError(path + ":" + std::to_string(n) + ": expected x,y,z, got '" + escape_field(line) + "'");
        }
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
            throw FormatError(path + ":" + std::to_string(n) + ": non-finite position");
        first_line = false;
        out.push_back({v[0], v[1], v[2]});
    }
    if (in.bad()) throw IoError(path + ": read error");
    if (out.empty()) throw FormatError(path + ": no positions (expected lines of x,y,z)");
    return out;
}

struct Plane {
    int axis = 2;
    double at = 0;
};

Plane parse_plane(const std::string& s) {
    const auto eq = s.find('=');
    if (eq != 1 || (s[0] != 'x' && s[0] != 'y' && s[0] != 'z'))
        throw UsageError("--plane: expected x=V, y=V or z=V, got '" + s + "'");
    return {s[0] - 'x', parse_finite(s.substr(2), "--plane")};
}

}  // namespace

int cmd_probe(int argc, char** argv) {
    Args a("probe", "POINTS... --at x,y,z [--at ...] | --at-file FILE [-o out.csv]",
           "Value and gradient of a meshless field built from scattered points, at world positions.\n"
           "Writes CSV with the header x,y,z,value,gx,gy,gz (stdout by default). NaN marks positions the\n"
           "data does not reach (see --max-gap).");
    a.option("at", "", "X,Y,Z", "a position (repeatable)").repeatable()
        .option("at-file", "", "FILE", "positions, three numbers per line (CSV or whitespace; header allowed); - = stdin")
        .option("output", "o", "FILE", "CSV output, '-' = stdout", "-");
    add_field_options(a, /*with_coverage=*/true, kDataFieldDefaultHelp);
    add_quiet_option(a);
    a.positionals(1, 1000);
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string csv = require_output_extension(a.get_or("output", "-"), ".csv", "-o", "CSV");
    std::vector<Vec3> at;
    for (const std::string& s : a.get_all("at")) {
        double v[3];
        char tail;
        if (std::sscanf(s.c_str(), "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3 || !std::isfinite(v[0]) ||
            !std::isfinite(v[1]) || !std::isfinite(v[2]))
            throw UsageError("--at: expected x,y,z, got '" + s + "'");
        at.push_back({v[0], v[1], v[2]});
    }
    if (auto f = a.get("at-file")) {
        const auto more = read_positions(*f);
        at.insert(at.end(), more.begin(), more.end());
    }
    if (at.empty()) throw UsageError("nothing to probe: give --at x,y,z or --at-file FILE");
    const PointSet pts = read_points_arg(a);
    const auto field = build_field(a, pts, data_field_default(a.positional()));
    // query positions -> field -> CSV
    const std::size_t positions = at.size();
    ProgressMeter meter("meshless probe", "positions", static_cast<double>(positions), progress_wanted(a), progress_delay());
    QueryListSource source(std::move(at), /*want_grad=*/true);
    FieldEvaluateStage evaluate(*field.field, field.coverage.get(), field.extrapolate);
    ProbeCsvSink sink(csv);
    ProgressStage progress([&](double n) { meter.add(n); });
    const Stage* stages[] = {&evaluate, &progress};
    run_pipeline(source, stages, sink, {threads(a)});
    meter.done();
    report_support(a, field, evaluate, positions);
    return 0;
}

int cmd_slice(int argc, char** argv) {
    Args a("slice", "POINTS... --plane z=V -o slice.png [--size 1024x1024]",
           "Renders a colour-mapped slice through a meshless field built from scattered points, over the\n"
           "points' bounding box in the plane, with the data points near the plane drawn as dots.\n"
           "Grey marks where the data does not reach (see --max-gap).");
    a.option("plane", "", "AXIS=V", "the slicing plane, e.g. z=0.5 (world units)")
        .option("output", "o", "FILE", "PNG output (required)")
        .option("size", "", "WxH", "largest image size, 2..16384 per side (3 bytes a pixel must fit in memory); the aspect follows the bounding box", "1024x1024")
        .option("range", "", "LO,HI", "values mapped to the ends of the colour map (default: the data's range)")
        .option("colormap", "", "NAME", "coolwarm | viridis | gray", "coolwarm")
        .option("near", "", "D", "overlay data points within D of the plane (default: half the mean point spacing)")
        .flag("colorbar", "draw the colour map and its value range (--range or the data's) as a legend bar at the right edge");
    add_field_options(a, /*with_coverage=*/true, kDataFieldDefaultHelp);
    add_quiet_option(a);
    a.positionals(1, 1000);
    if (!a.parse(argc, argv, 2)) return 0;
    const Plane plane = parse_plane(a.require("plane"));
    const std::string png = require_output_extension(a.require("output"), ".png", "-o", "a PNG image");
    Colormap cmap;
    if (!parse_colormap(a.get_or("colormap", "coolwarm"), cmap)) throw UsageError("--colormap: expected coolwarm, viridis or gray");
    const auto [W, H] = parse_size(a.get_or("size", "1024x1024"), "--size", 2, 16384);
    check_option_fits(a, "--size " + a.get_or("size", "1024x1024"), "the RGB image (3 bytes a pixel)", image_bytes(W, H, 3),
                      "give a smaller --size");
    const PointSet pts = read_points_arg(a);
    const auto field = build_field(a, pts, data_field_default(a.positional()));
    const auto [lo, hi] = pts.bounds();
    const int u = (plane.axis + 1) % 3, v = (plane.axis + 2) % 3;  // image axes: u right, v up
    const int ua = std::min(u, v), va = std::max(u, v);             // x before y before z
    const double eu = std::max(hi[ua] - lo[ua], 1e-12), ev = std::max(hi[va] - lo[va], 1e-12);
    const double px = std::max(eu / W, ev / H);  // world units per pixel, aspect kept
    const int w = std::max(2, static_cast<int>(std::ceil(eu / px))), h = std::max(2, static_cast<int>(std::ceil(ev / px)));
    std::array<double, 2> range = pts.value_range();
    if (auto r = a.get("range")) {
        if (std::sscanf(r->c_str(), "%lf,%lf", &range[0], &range[1]) != 2 || !(range[0] < range[1]))
            throw UsageError("--range: expected LO,HI with LO < HI, got '" + *r + "'");
    }
    // pixel centres -> field -> colour-mapped image
    PlaneRaster raster;
    raster.axis = plane.axis;
    raster.at = plane.at;
    raster.lo_u = lo[ua];
    raster.lo_v = lo[va];
    raster.pixel = px;
    raster.width = w;
    raster.height = h;
    PlaneRasterSource source(raster);
    ProgressMeter meter("meshless slice", "pixels", static_cast<double>(w) * h, progress_wanted(a), progress_delay());
    FieldEvaluateStage evaluate(*field.field, field.coverage.get(), field.extrapolate);
    SliceImageSink sink(w, h, cmap, range[0], range[1]);
    ProgressStage progress([&](double n) { meter.add(n); });
    const Stage* stages[] = {&evaluate, &progress};
    run_pipeline(source, stages, sink, {threads(a)});
    meter.done();
    report_support(a, field, evaluate, static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    if (evaluate.uncovered() == static_cast<std::size_t>(w) * static_cast<std::size_t>(h))
        std::fprintf(stderr, "meshless slice: warning: the plane %c=%g does not meet the data (every pixel is outside it)\n",
                     'x' + plane.axis, plane.at);
    Image& img = sink.image();
    // overlay: data points near the plane, as 3x3 dark dots
    double near = 0;
    if (auto d = a.get("near")) near = parse_finite(*d, "--near");
    else {
        const Vec3 ext = hi - lo;
        double vol = 1;
        int k = 0;
        for (int d2 = 0; d2 < 3; ++d2)
            if (ext[d2] > 0) vol *= ext[d2], ++k;
        near = 0.5 * (k ? std::pow(vol / std::max<std::size_t>(1, pts.size()), 1.0 / k) : 0);
    }
    std::size_t shown = 0;
    for (const Vec3& p : pts.pos) {
        if (std::abs(p[plane.axis] - plane.at) > near) continue;
        const int c = static_cast<int>((p[ua] - lo[ua]) / px), r = h - 1 - static_cast<int>((p[va] - lo[va]) / px);
        ++shown;
        for (int dr = -1; dr <= 1; ++dr)
            for (int dc = -1; dc <= 1; ++dc) {
                const int rr = r + dr, cc = c + dc;
                if (rr < 0 || rr >= h || cc < 0 || cc >= w) continue;
                std::uint8_t* px8 = &img.rgb[3 * (static_cast<std::size_t>(rr) * w + cc)];
                px8[0] = px8[1] = px8[2] = (dr == 0 && dc == 0) ? 255 : 20;
            }
    }
    if (a.has("colorbar")) draw_colorbar(img, cmap, range[0], range[1]);
    write_png(img, png);
    if (a.has("stats"))
        std::fprintf(stderr, "slice: %dx%d pixels, %g world units per pixel, %zu data points within %g of the plane\n", w, h, px,
                     shown, near);
    return 0;
}

int cmd_resample(int argc, char** argv) {
    Args a("resample", "POINTS... --grid X,Y,Z -o vol.nrrd",
           "Resamples a meshless field built from scattered points onto a regular grid over the points'\n"
           "bounding box (float32 NRRD), for the isosurface commands and other tools. Voxels the data does\n"
           "not reach (see --max-gap) are NaN.");
    a.option("grid", "", "X,Y,Z", "output grid samples along x, y, z (required)")
        .deprecated_alias("dims")
        .option("output", "o", "FILE", "NRRD output (required)");
    add_field_options(a, /*with_coverage=*/true, kDataFieldDefaultHelp);
    add_quiet_option(a);
    a.positionals(1, 1000);
    if (!a.parse(argc, argv, 2)) return 0;
    const auto d = a.get_triple("grid");
    if (!d) throw UsageError("missing required option --grid (see meshless resample --help)");
    GridSpec g;
    for (int i = 0; i < 3; ++i) {
        if ((*d)[i] < 2 || (*d)[i] > 4096 || (*d)[i] != std::floor((*d)[i])) throw UsageError("--grid: expected integers 2..4096");
        g.dims[i] = static_cast<std::int64_t>((*d)[i]);
    }
    const std::string out = require_output_extension(a.require("output"), ".nrrd", "-o", "a float32 volume (NRRD)");
    const PointSet pts = read_points_arg(a);
    const auto field = build_field(a, pts, data_field_default(a.positional()));
    const auto [lo, hi] = pts.bounds();
    for (int i = 0; i < 3; ++i) {
        g.origin[i] = lo[i];
        g.spacing[i] = hi[i] > lo[i] ? (hi[i] - lo[i]) / static_cast<double>(g.dims[i] - 1) : 1.0;
    }
    // grid samples -> field -> NRRD
    GridRasterSource source(g);
    ProgressMeter meter("meshless resample", "voxels", static_cast<double>(g.voxel_count()), progress_wanted(a), progress_delay());
    FieldEvaluateStage evaluate(*field.field, field.coverage.get(), field.extrapolate);
    NrrdVolumeSink sink(g, out, "meshless resample: " + std::string(field.field->name()) + " field of " + std::to_string(pts.size()) + " points");
    ProgressStage progress([&](double n) { meter.add(n); });
    const Stage* stages[] = {&evaluate, &progress};
    run_pipeline(source, stages, sink, {threads(a)});
    meter.done();
    report_support(a, field, evaluate, static_cast<std::size_t>(g.voxel_count()));
    return 0;
}

}  // namespace meshless::cli
