// Looking at scattered data directly through meshless fields (dissertation chapters 4-5, 7):
//   meshless probe POINTS --at x,y,z ...        value and gradient at given positions (CSV)
//   meshless slice POINTS --plane z=0.5 -o s.png colour-mapped slice with the nearby points overlaid
//   meshless resample POINTS --grid X,Y,Z -o v.nrrd   the field on a regular grid
// Each parses its options, builds or loads the field (cli/field_cli.hpp) and calls its recipe
// (stream/field_queries.hpp), then prints what the evaluation found.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/field_cli.hpp"
#include "cli/progress_meter.hpp"
#include "formats/position_list.hpp"
#include "stream/field_queries.hpp"
#include "stream/store_field_queries.hpp"

namespace meshless::cli {

namespace {

/// A query run under --threads that counts positions on `meter`, and clears it and reports the
/// support (with or without a support test, `mode` outside the data; then `more`) once the field was evaluated.
FieldQueryRun query_run(const Args& a, bool coverage, Extrapolate mode, ProgressMeter& meter,
                        std::function<void(const FieldQueryStats&)> more = {}) {
    return {threads(a), [&meter](double n) { meter.add(n); }, [&a, coverage, mode, &meter, more](const FieldQueryStats& s) {
                meter.done();
                report_field_support(stderr, a.command(), coverage, mode, s, a.has("stats"));
                if (more) more(s);
            }};
}
FieldQueryRun query_run(const Args& a, const BuiltField& f, ProgressMeter& meter, std::function<void(const FieldQueryStats&)> more = {}) {
    return query_run(a, f.coverage != nullptr, f.extrapolate, meter, std::move(more));
}
FieldQueryRun query_run(const Args& a, const StoreQueryParams& p, ProgressMeter& meter, std::function<void(const FieldQueryStats&)> more = {}) {
    return query_run(a, p.max_gap > 0, p.extrapolate, meter, std::move(more));
}

/// A point store queried slab by slab (stream/store_field_queries.hpp): the store, its plan and
/// the query parameters; the --stats line.
struct StoreSlabQuery {
    explicit StoreSlabQuery(const Args& args) : a(args), in(open_store_queries(args.positional()[0])), p(store_query_params(args)) {}
    void print_stats() const {
        if (a.has("stats")) print_store_query_stats(stderr, a.command().c_str(), in.plan, report);
    }
    const Args& a;
    StoreQueries in;
    StoreQueryParams p;
    StoreQueryReport report;
};

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
    add_store_memory_option(a);
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
    if (queries_store_slabs(a)) {
        StoreSlabQuery sq(a);
        ProgressMeter meter = ProgressMeter::of(a, "positions", static_cast<double>(at.size()));
        probe_store_field(*sq.in.store, sq.in.plan, sq.p, std::move(at), csv, query_run(a, sq.p, meter), &sq.report);
        sq.print_stats();
        return 0;
    }
    const PointSet pts = read_points_arg(a);
    const auto field = build_field(a, pts, data_field_default(a.positional()));
    ProgressMeter meter = ProgressMeter::of(a, "positions", static_cast<double>(at.size()));
    probe_field(field, std::move(at), csv, query_run(a, field, meter));
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
        .option("near", "", "D", "overlay data points within D >= 0 of the plane (default: half the mean point spacing)")
        .flag("colorbar", "draw the colour map and its value range (--range or the data's) as a legend bar at the right edge");
    add_field_options(a, /*with_coverage=*/true, kDataFieldDefaultHelp);
    add_store_memory_option(a);
    add_quiet_option(a);
    a.positionals(1, 1000);
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string plane = a.require("plane");
    if (plane.find('=') != 1 || (plane[0] != 'x' && plane[0] != 'y' && plane[0] != 'z'))
        throw UsageError("--plane: expected x=V, y=V or z=V, got '" + plane + "'");
    const int axis = plane[0] - 'x';
    const double at = parse_finite(plane.substr(2), "--plane");
    SliceRequest r;
    r.output = require_output_extension(a.require("output"), ".png", "-o", "a PNG image");
    if (!parse_colormap(a.get_or("colormap", "coolwarm"), r.colormap)) throw UsageError("--colormap: expected coolwarm, viridis or gray");
    const auto [W, H] = parse_size(a.get_or("size", "1024x1024"), "--size", 2, 16384);
    check_option_fits(a, "--size " + a.get_or("size", "1024x1024"), "the RGB image (3 bytes a pixel)", image_bytes(W, H, 3),
                      "give a smaller --size");
    std::optional<StoreSlabQuery> sq;
    PointSet pts;
    BuiltField field;
    if (queries_store_slabs(a)) {
        sq.emplace(a);
        r.range = sq->in.plan.value_range;
    } else {
        pts = read_points_arg(a);
        field = build_field(a, pts, data_field_default(a.positional()));
        r.range = pts.value_range();
    }
    if (auto v = a.get("range")) {
        if (std::sscanf(v->c_str(), "%lf,%lf", &r.range[0], &r.range[1]) != 2 || !(r.range[0] < r.range[1]))
            throw UsageError("--range: expected LO,HI with LO < HI, got '" + *v + "'");
    }
    if (auto d = a.get("near")) {
        r.near = parse_finite(*d, "--near");
        if (*r.near < 0) throw UsageError("--near: expected a distance >= 0, got " + *d);
    }
    r.colorbar = a.has("colorbar");
    const PlaneRaster raster = sq ? slice_raster(sq->in.plan.frame.bounds, axis, at, W, H) : slice_raster(pts, axis, at, W, H);
    ProgressMeter meter = ProgressMeter::of(a, "pixels", static_cast<double>(raster.width) * raster.height);
    const auto outside = [&](const FieldQueryStats& s) {
        if (s.uncovered == s.positions)
            std::fprintf(stderr, "meshless slice: warning: the plane %c=%g does not meet the data (every pixel is outside it)\n",
                         'x' + axis, at);
    };
    SliceResult res;
    if (sq) {
        res = slice_store_field(*sq->in.store, sq->in.plan, sq->p, raster, r, query_run(a, sq->p, meter, outside), &sq->report);
        sq->print_stats();
    } else {
        res = slice_field(field, pts, raster, r, query_run(a, field, meter, outside));
    }
    if (a.has("stats"))
        std::fprintf(stderr, "slice: %dx%d pixels, %g world units per pixel, %zu data points within %g of the plane\n",
                     raster.width, raster.height, raster.pixel, res.shown, res.near);
    return 0;
}

int cmd_resample(int argc, char** argv) {
    Args a("resample", "POINTS... --grid X,Y,Z -o vol.nrrd",
           "Resamples a meshless field built from scattered points onto a regular grid over the points'\n"
           "bounding box (float32 NRRD), for the isosurface commands and other tools. Voxels the data does\n"
           "not reach (see --max-gap) are NaN.");
    a.option("grid", "", "X,Y,Z", "output grid samples along x, y, z, 2..4096 each (required)")
        .deprecated_alias("dims")
        .option("output", "o", "FILE", "NRRD output (required)");
    add_field_options(a, /*with_coverage=*/true, kDataFieldDefaultHelp);
    add_store_memory_option(a);
    add_quiet_option(a);
    a.positionals(1, 1000);
    if (!a.parse(argc, argv, 2)) return 0;
    const auto d = a.get_triple("grid");
    if (!d) throw UsageError("missing required option --grid (see meshless resample --help)");
    std::array<std::int64_t, 3> dims{};
    for (int i = 0; i < 3; ++i) {
        if ((*d)[i] < 2 || (*d)[i] > 4096 || (*d)[i] != std::floor((*d)[i])) throw UsageError("--grid: expected integers 2..4096");
        dims[i] = static_cast<std::int64_t>((*d)[i]);
    }
    const std::string out = require_output_extension(a.require("output"), ".nrrd", "-o", "a float32 volume (NRRD)");
    if (queries_store_slabs(a)) {
        StoreSlabQuery sq(a);
        const GridSpec g = resample_grid(sq.in.plan.frame.bounds, dims);
        ProgressMeter meter = ProgressMeter::of(a, "voxels", static_cast<double>(g.voxel_count()));
        resample_store_field(*sq.in.store, sq.in.plan, sq.p, g, out, query_run(a, sq.p, meter), &sq.report);
        sq.print_stats();
        return 0;
    }
    const PointSet pts = read_points_arg(a);
    const auto field = build_field(a, pts, data_field_default(a.positional()));
    const GridSpec g = resample_grid(pts, dims);
    ProgressMeter meter = ProgressMeter::of(a, "voxels", static_cast<double>(g.voxel_count()));
    resample_field(field, pts, g, out, query_run(a, field, meter));
    return 0;
}

}  // namespace meshless::cli
