#include "cli/scattered_isosurface.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/field_cli.hpp"
#include "cli/isosurface_graph.hpp"
#include "cli/mpi_session.hpp"
#include "cli/multiblock_isosurface.hpp"
#include "cli/point_set_cli.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/barycentric_lattice.hpp"
#include "kernels/errors.hpp"
#include "kernels/marching_stencils.hpp"
#include "kernels/scattered_binning_grid.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/runner.hpp"
#include "stream/stencil_seed_stage.hpp"
#include "stream/stencil_source.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless::cli {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr const char* kPointsWhat = "an oriented point set";

void add_binning_options(Args& a) {
    a.option("max-cells", "", "N", "cap on the binning grid's cells (section 5.3): a finer grid is coarsened, with a warning",
             std::to_string(BinningGridParams{}.max_cells))
        .option("max-level", "", "L", "cap on the binning level l_b (2^L cells per axis)", std::to_string(BinningGridParams{}.max_level));
}

BinningGridParams binning_params(const Args& a) {
    BinningGridParams p;
    const long long cells = a.get_int_or("max-cells", p.max_cells);
    if (cells < 27 || cells > (1LL << 31)) throw UsageError("--max-cells: expected 27..2^31 (27 = one 3x3x3 stencil)");
    p.max_cells = cells;
    const long long l = a.get_int_or("max-level", p.max_level);
    if (l < 0 || l > 12) throw UsageError("--max-level: expected 0..12");
    p.max_level = static_cast<int>(l);
    return p;
}

struct ScatteredInput {
    PointSet points;
    BinningGrid grid;
    BinnedPoints bins;
    std::string source;  ///< file names joined by ','
    double read_seconds = 0, octree_seconds = 0;
};

std::string joined_names(const std::vector<std::string>& paths) {
    std::string s;
    for (const auto& p : paths) {
        if (!s.empty()) s += ',';
        s += std::filesystem::path(p).filename().string();
    }
    return s;
}

std::size_t distinct_positions(const std::vector<Vec3>& pos, std::size_t enough) {
    std::vector<Vec3> p(pos);
    std::sort(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) {
        return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
    });
    std::size_t n = p.empty() ? 0 : 1;
    for (std::size_t i = 1; i < p.size() && n < enough; ++i)
        if (p[i].x != p[i - 1].x || p[i].y != p[i - 1].y || p[i].z != p[i - 1].z) ++n;
    return n;
}

const char* axis_name(int a) { return a == 0 ? "x" : (a == 1 ? "y" : "z"); }

ScatteredInput read_scattered(const Args& a) {
    if (a.positional().empty()) throw UsageError("missing POINTS argument (see meshless " + a.command() + " --help)");
    ScatteredInput in;
    in.source = joined_names(a.positional());
    const BinningGridParams bp = binning_params(a);
    auto t0 = Clock::now();
    in.points = read_points_arg(a);
    in.read_seconds = since(t0);
    const std::string& name = a.positional()[0];
    if (!in.points.has_values)
        throw FormatError(name + ": the points carry no values (positions only); there is nothing to contour");
    if (in.points.dropped_nonfinite > 0)
        std::fprintf(stderr, "meshless: warning: %s: %llu points with a NaN/Inf position or value dropped\n", name.c_str(),
                     static_cast<unsigned long long>(in.points.dropped_nonfinite));
    if (distinct_positions(in.points.pos, 4) < 4)
        throw FormatError(name + ": fewer than 4 distinct point positions; a volume needs at least 4 points not all in one place");
    t0 = Clock::now();
    in.grid = make_binning_grid(in.points.pos, bp);
    in.bins = bin_points(in.grid, in.points.pos);
    in.octree_seconds = since(t0);
    const int degenerate = int(in.grid.degenerate[0]) + int(in.grid.degenerate[1]) + int(in.grid.degenerate[2]);
    if (degenerate > 0) {
        std::string axes;
        for (int ax = 0; ax < 3; ++ax)
            if (in.grid.degenerate[static_cast<std::size_t>(ax)]) axes += std::string(axes.empty() ? "" : ", ") + axis_name(ax);
        std::fprintf(stderr,
                     "meshless: warning: %s: all points lie on a %s (no extent along %s): the binning grid gives %s one "
                     "cell; the surface is the field's where it defines one off the data\n",
                     name.c_str(), degenerate == 1 ? "plane" : "line", axes.c_str(), degenerate == 1 ? "that axis" : "those axes");
    }
    if (in.grid.coarsened)
        std::fprintf(stderr,
                     "meshless: warning: %s: the binning rule asks for level %d (%lld cells); coarsened to level %d "
                     "(%lld cells) by --max-cells %lld / --max-level %d: stencils hold more points\n",
                     name.c_str(), in.grid.rule_level,
                     static_cast<long long>(std::pow(std::ldexp(1.0, in.grid.rule_level) + 2, 3 - degenerate) * std::pow(3.0, degenerate)),
                     in.grid.level, static_cast<long long>(in.grid.cell_count()), static_cast<long long>(bp.max_cells), bp.max_level);
    return in;
}

std::string triple(const Vec3& v) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g", v.x, v.y, v.z);
    return buf;
}

/// What generate writes and isosurface records (the same keys on both paths).
StreamMeta scattered_meta(const ScatteredInput& in, double iso, int n, const std::string& producer) {
    StreamMeta m;
    const auto range = in.points.value_range();
    m.set("source", in.source);
    m.set("method", "scattered");
    m.set("iso", iso);
    m.set("samples", std::to_string(n));
    m.set("points", std::to_string(in.points.size()));
    m.set("binning_level", std::to_string(in.grid.level));
    m.set("value_min", range[0]);
    m.set("value_max", range[1]);
    // the frame: the binning grid's interior (the points' box)
    m.set("bounds_lo", triple(in.grid.bounds[0]));
    m.set("bounds_hi", triple(in.grid.bounds[1]));
    m.set("volume_bounds_lo", triple(in.grid.bounds[0]));
    m.set("volume_bounds_hi", triple(in.grid.bounds[1]));
    m.set("producer", producer);
    return m;
}

bool iso_in_range(const ScatteredInput& in, double iso) {
    const auto r = in.points.value_range();
    return iso >= r[0] && iso <= r[1];
}

void print_scattered_stats(const char* cmd, const ScatteredInput& in, const StencilSeedStats& s, int n) {
    const auto& g = in.grid;
    std::fprintf(stderr,
                 "%s: %zu points (%llu NaN/Inf dropped); binning level %d (rule %d%s), grid %lldx%lldx%lld = %lld cells, "
                 "%lld empty (%lld inside the border layer), at most %u points in a cell\n",
                 cmd, in.points.size(), static_cast<unsigned long long>(in.points.dropped_nonfinite), g.level, g.rule_level,
                 g.coarsened ? ", coarsened" : "", static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]),
                 static_cast<long long>(g.dims[2]), static_cast<long long>(g.cell_count()), static_cast<long long>(in.bins.empty_cells),
                 static_cast<long long>(in.bins.empty_interior_cells), in.bins.max_per_cell);
    std::fprintf(stderr,
                 "%s: %lld stencils (%lld crossed, largest %lld points), %lld regularisation points made on the fly, "
                 "%lld Delaunay failures, %lld tets (%lld owned, %lld with a NaN value), %lld triangles (%lld of zero area), "
                 "%lld seeds (n = %d, %zu per triangle)\n",
                 cmd, static_cast<long long>(s.stencils), static_cast<long long>(s.crossed_stencils),
                 static_cast<long long>(s.max_stencil_points), static_cast<long long>(s.regularisation_points),
                 static_cast<long long>(s.delaunay_failures), static_cast<long long>(s.tets), static_cast<long long>(s.owned_tets),
                 static_cast<long long>(s.nonfinite_tets), static_cast<long long>(s.triangles),
                 static_cast<long long>(s.zero_area_triangles), static_cast<long long>(s.seeds), n, lattice_size(n));
}

void add_scattered_options(Args& a) {
    add_samples_option(a);
    add_binning_options(a);
}

}  // namespace

// ------------------------------------------------------------------ dispatch

bool scattered_invocation(const std::vector<std::string>& positionals) {
    if (positionals.empty() || blocks_invocation(positionals)) return false;
    const std::string& p = positionals[0];
    if (looks_like_point_set(p)) return true;
    std::string e = std::filesystem::path(p).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    std::error_code ec;
    return e == ".ply" && std::filesystem::is_regular_file(p, ec) && !looks_like_volume(p);
}

// ------------------------------------------------------------------ isosurface POINTS

int isosurface_scattered(int argc, char** argv) {
    const auto t_start = Clock::now();
    Args a("isosurface", "POINTS --iso V -o out.ply [--png out.png] [--field rbf-grid|mpu|global-rbf|F.mlf] [--samples N] [options]",
           "Isosurface straight from scattered data (dissertation chapter 5): the points are binned in the grid\n"
           "of section 5.3 (octree, median of the depth-first levels, one surrounding layer of cells); a 3x3x3\n"
           "stencil marches over alternate cells: its points, plus one regularisation point with the field's value\n"
           "at the centre of each empty cell (made on the fly, never stored), are tetrahedralised by CGAL's Delaunay\n"
           "(section 5.4), marching tetrahedra contours the tetrahedra the stencil owns, the triangles are sampled\n"
           "on a barycentric lattice of N(N+1)/2 interior points, and every sample is projected onto the field's\n"
           "isosurface by safeguarded Newton iteration (section 5.6). Writes an oriented point set (binary PLY:\n"
           "x y z nx ny nz radius value, or .vtp) and/or a splatted PNG.\n"
           "POINTS: CSV/TSV/text, PLY, VTP, raw float32 records, .npy (see meshless info).");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "point set output: .ply or .vtp; '-' = stdout")
        .option("png", "", "FILE", "also render the points to this PNG");
    add_geometry_format_option(a);
    add_scattered_options(a);
    add_newton_options(a);
    add_field_options(a, /*with_coverage=*/false);
    add_camera_options(a);
    add_color_options(a);
    a.positionals(1, 1u << 20);
    a.epilog("examples: meshless sample bucky.raw -n 20000 -o bucky.ply && meshless isosurface bucky.ply --iso 100 -o b.ply --png b.png --stats\n"
             "pipes:    meshless fit POINTS -o f.mlf && meshless generate POINTS --iso V | meshless project --field f.mlf | meshless splat -o img.png\n");
    if (!a.parse(argc, argv, 2)) return 0;
    if (launched_world_size() > 1)
        throw UsageError("scattered inputs are not split over MPI ranks yet: run meshless isosurface POINTS without mpirun");
    const double iso = parse_finite(a.require("iso"), "--iso");
    const auto out = a.get("output");
    const auto png = a.get("png");
    if (!out && !png) throw UsageError("nothing to write: give -o FILE and/or --png FILE");
    if (out) geometry_output_format(a, *out, kPointsWhat);
    if (png) require_output_extension(*png, ".png", "--png", "a PNG image");
    if (out && png && *out == *png && (*out == "-" || !is_streaming_output(*out)))
        throw UsageError("-o and --png name the same output '" + *out + "'");
    const int n = lattice_n(a);
    const FieldProjectParams np = newton_params(a);
    (void)binning_params(a);
    RenderSettings rs = render_settings(a);
    const ColorChoice cc = color_choice(a);
    if (cc.request == ColorRequest::block) throw UsageError("scattered points have no blocks; --color block needs multiblock input");
    const int nthreads = threads(a);
    if (!field_file_arg(a)) (void)field_params(a);  // option errors before any reading

    ScatteredInput in = read_scattered(a);
    apply_color(rs, color_by(cc, ColorBy::none), cc, cc.range ? *cc.range : std::array<double, 2>{iso, iso});
    const bool crossed = iso_in_range(in, iso);
    if (!crossed) warn_if_iso_outside(iso, in.points.value_range(), in.source);
    StreamMeta meta = scattered_meta(in, iso, n, a.command_line());

    // the field: only when the isovalue is within the data (an empty output needs none)
    auto t0 = Clock::now();
    BuiltField field;
    std::string field_name = a.get_or("field", "rbf-grid");
    if (crossed) {
        field = build_field(a, in.points);
        field_name = field.field->name();
    }
    const double field_seconds = since(t0);
    meta.set("projection", "newton");
    meta.set("field", field_name);
    meta.set("tolerance", np.seed_tolerance);

    const StencilGrid sg(in.grid.dims);
    std::optional<StencilSeedStage> seed;
    std::optional<FieldProjectStage> project;
    IsoSplatResult unused;
    t0 = Clock::now();
    const std::size_t points = run_to_outputs(geometry_output(a, kPointsWhat), png, meta, rs, nthreads, [&](const Stage* draw, Sink& sink) {
        const auto g0 = Clock::now();
        if (!field.field) {
            RecordVectorSource empty(std::vector<PointRecord>{});
            const Stage* stages[] = {draw};
            run_pipeline(empty, std::span<const Stage* const>(stages, draw ? 1 : 0), sink, {nthreads});
        } else {
            StencilSource source(sg);
            seed.emplace(StencilInput{in.grid, in.bins, in.points.pos, in.points.value, *field.field}, iso, n);
            project.emplace(*field.field, iso, np);
            const Stage* stages[] = {&*seed, &*project, draw};
            run_pipeline(source, std::span<const Stage* const>(stages, draw ? 3 : 2), sink, {nthreads});
        }
        IsoSplatResult r;
        r.seconds = since(g0);
        return r;
    }, unused, /*parallel_draw=*/true, /*with_blocks=*/false);
    const double graph_seconds = since(t0);

    if (a.has("stats")) {
        const char* cmd = "isosurface";
        const StencilSeedStats s = seed ? seed->stats() : StencilSeedStats{};
        print_scattered_stats(cmd, in, s, n);
        if (project) print_newton_stats(cmd, field_name, np, project->stats(), project->busy_seconds());
        std::fprintf(stderr,
                     "%s: %zu points; time: read %.3f s, octree + binning %.3f s, field %.3f s, regularisation %.3f s busy, "
                     "isosurface (stencils + Delaunay + seeds + Newton + output) %.3f s (busy: stencils %.3f s of which "
                     "Delaunay %.3f s, Newton %.3f s over %d thread(s)), total %.3f s\n",
                     cmd, points, in.read_seconds, in.octree_seconds, field_seconds, 1e-9 * double(s.regularisation_ns), graph_seconds,
                     seed ? seed->busy_seconds() : 0.0, 1e-9 * double(s.delaunay_ns), project ? project->busy_seconds() : 0.0,
                     nthreads, since(t_start));
    }
    return 0;
}

// ------------------------------------------------------------------ generate POINTS

int generate_scattered(int argc, char** argv) {
    Args a("generate", "POINTS --iso V [--field KIND|F.mlf] [--samples N] [-o FILE|-]",
           "The seeds of the scattered-data isosurface (dissertation sections 5.3-5.6): binning grid, marching\n"
           "stencils regularised with the field's values (built from POINTS, or --field FILE.mlf), local Delaunay,\n"
           "marching tetrahedra, barycentric lattice; written as a binary seed stream (stdout by default) for\n"
           "`meshless project --field F.mlf` (or --field KIND POINTS).");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "stream output, '-' = stdout", "-")
        .flag("compress", "zstd-compress the stream's DATA frames");
    add_scattered_options(a);
    add_field_options(a, /*with_coverage=*/false);
    a.positionals(1, 1u << 20);
    a.epilog("example: meshless fit pts.ply -o f.mlf && meshless generate pts.ply --iso 0.5 --field f.mlf | meshless project --field f.mlf | meshless splat -o img.png\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = parse_finite(a.require("iso"), "--iso");
    const int n = lattice_n(a);
    (void)binning_params(a);
    const int nthreads = threads(a);
    if (!field_file_arg(a)) (void)field_params(a);
    const auto t0 = Clock::now();
    ScatteredInput in = read_scattered(a);
    const bool crossed = iso_in_range(in, iso);
    if (!crossed) warn_if_iso_outside(iso, in.points.value_range(), in.source);
    BuiltField field;
    if (crossed) field = build_field(a, in.points);
    const double field_seconds = since(t0) - in.read_seconds - in.octree_seconds;
    BinaryStreamOutput out(a.get_or("output", "-"));
    StreamSink sink(out.f, out.name, RecordKind::seed, scattered_meta(in, iso, n, a.command_line()), a.has("compress"));
    std::optional<StencilSeedStage> seed;
    if (field.field) {
        StencilSource source{StencilGrid(in.grid.dims)};
        seed.emplace(StencilInput{in.grid, in.bins, in.points.pos, in.points.value, *field.field}, iso, n);
        const Stage* stages[] = {&*seed};
        run_pipeline(source, stages, sink, {nthreads});
    } else {
        RecordVectorSource empty(std::vector<PointRecord>{});
        run_pipeline(empty, {}, sink, {nthreads});
    }
    out.commit();
    if (a.has("stats")) {
        print_scattered_stats("generate", in, seed ? seed->stats() : StencilSeedStats{}, n);
        std::fprintf(stderr, "generate: read %.3f s, octree + binning %.3f s, field %.3f s, total %.3f s\n", in.read_seconds,
                     in.octree_seconds, field_seconds, since(t0));
    }
    return 0;
}

}  // namespace meshless::cli
