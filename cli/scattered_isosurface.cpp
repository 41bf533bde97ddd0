#include "cli/scattered_isosurface.hpp"
#include "cli/progress_meter.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_invoke.h>

#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/stream_output.hpp"
#include "cli/field_cli.hpp"
#include "cli/mpi_session.hpp"
#include "cli/multiblock_isosurface.hpp"
#include "cli/point_set_cli.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/barycentric_lattice.hpp"
#include "kernels/errors.hpp"
#include "kernels/marching_stencils.hpp"
#include "kernels/point_coverage.hpp"
#include "kernels/scattered_binning_grid.hpp"
#include "stream/dedup_sink.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/progress_stage.hpp"
#include "stream/runner.hpp"
#include "stream/stencil_seed_stage.hpp"
#include "stream/stencil_ranks.hpp"
#include "stream/stencil_source.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless::cli {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr const char* kPointsWhat = "an oriented point set";

void add_binning_options(Args& a) {
    a.option("max-cells", "", "N", "cap on the binning grid's cells (section 5.3), 27..2^31 (4 bytes a cell must fit in "
                                   "memory): a finer grid is coarsened, with a warning",
             std::to_string(BinningGridParams{}.max_cells))
        .option("max-level", "", "L", "cap on the binning level l_b (2^L cells per axis)", std::to_string(BinningGridParams{}.max_level))
        .option("reg-gap", "", "F",
                "a regularisation point farther than F x the local point spacing (8th-neighbour distance) from the data "
                "gets no value (no surface where no data is); 0 = every empty cell gets the field's value", "4");
}

double reg_gap(const Args& a) {
    const double f = parse_finite(a.get_or("reg-gap", "4"), "--reg-gap");
    if (f < 0) throw UsageError("--reg-gap: expected a factor >= 0");
    return f;
}

/// The most data points one 3x3x3 stencil holds (before regularisation).
std::int64_t largest_stencil(const BinningGrid& g, const BinnedPoints& b) {
    const StencilGrid sg(g.dims);
    std::int64_t most = 0;
    for (std::int64_t s = 0; s < sg.total(); ++s) {
        const auto m = sg.coords(s);
        const std::int64_t c[3] = {stencil_centre(m[0], g.dims[0]), stencil_centre(m[1], g.dims[1]), stencil_centre(m[2], g.dims[2])};
        std::int64_t n = 0;
        for (std::int64_t k = c[2] - 1; k <= c[2] + 1; ++k)
            for (std::int64_t j = c[1] - 1; j <= c[1] + 1; ++j) {
                const std::int64_t row = g.index(c[0] - 1, j, k);
                n += std::int64_t(b.start[static_cast<std::size_t>(row) + 3]) - std::int64_t(b.start[static_cast<std::size_t>(row)]);
            }
        most = std::max(most, n);
    }
    return most;
}

BinningGridParams binning_params(const Args& a) {
    BinningGridParams p;
    const long long cells = a.get_int_or("max-cells", p.max_cells);
    if (cells < 27 || cells > (1LL << 31)) throw UsageError("--max-cells: expected 27..2^31 (27 = one 3x3x3 stencil)");
    check_option_fits(a, "--max-cells " + std::to_string(cells), "a binning grid of that many cells (its index: 4 bytes a cell)",
                      static_cast<std::uint64_t>(cells) * 4, "a smaller --max-cells");
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
    std::unique_ptr<PointCoverage> coverage;  ///< --reg-gap > 0, built with the field (build_field_and_coverage)
    double reg_gap = 0;                       ///< --reg-gap
    double coverage_seconds = 0;
    std::string source;  ///< file names joined by ','
    double read_seconds = 0, octree_seconds = 0;
};

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

/// The field (only when `crossed`: an empty output needs none) and the regularisation's support test
/// (--reg-gap; in.coverage), built side by side under --threads: each has serial parts (the
/// support test's kd-tree; the field's merge of near-duplicates and octree root) that the other's
/// parallel parts overlap (10^6 points, 2 threads: 17.0 -> 15.4 s whole process). The seconds
/// are each one's own, overlapped; the bits do not depend on the thread count. share: as for build_field.
BuiltField build_field_and_coverage(const Args& a, ScatteredInput& in, bool crossed, double& field_seconds,
                                    const FitShare* share = nullptr) {
    BuiltField field;
    field_seconds = 0;
    if (!crossed) return field;
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads(a)));
    oneapi::tbb::parallel_invoke(
        [&] {
            const auto t0 = Clock::now();
            field = build_field(a, in.points, {}, share);
            field_seconds = since(t0);
        },
        [&] {
            if (in.reg_gap <= 0) return;
            const auto t0 = Clock::now();
            in.coverage = std::make_unique<PointCoverage>(in.points.pos, in.reg_gap);
            in.coverage_seconds = since(t0);
        });
    return field;
}

ScatteredInput read_scattered(const Args& a, bool warn = true) {
    if (a.positional().empty()) throw UsageError("missing POINTS argument (see meshless " + a.command() + " --help)");
    ScatteredInput in;
    in.source = joined_names(a.positional());
    const BinningGridParams bp = binning_params(a);
    auto t0 = Clock::now();
    in.points = read_points_arg(a);
    in.read_seconds = since(t0);
    const std::string& name = a.positional()[0];
    if (warn && in.points.dropped_nonfinite > 0)
        std::fprintf(stderr, "meshless: warning: %s: %llu points with a NaN/Inf position or value dropped\n", terminal_safe(name).c_str(),
                     static_cast<unsigned long long>(in.points.dropped_nonfinite));
    if (distinct_positions(in.points.pos, 4) < 4)
        throw FormatError(name + ": fewer than 4 distinct point positions; a volume needs at least 4 points not all in one place");
    t0 = Clock::now();
    in.grid = make_binning_grid(in.points.pos, bp);
    in.bins = bin_points(in.grid, in.points.pos);
    in.octree_seconds = since(t0);
    in.reg_gap = reg_gap(a);
    const int degenerate = int(in.grid.degenerate[0]) + int(in.grid.degenerate[1]) + int(in.grid.degenerate[2]);
    if (warn && degenerate > 0) {
        std::string axes;
        for (int ax = 0; ax < 3; ++ax)
            if (in.grid.degenerate[static_cast<std::size_t>(ax)]) axes += std::string(axes.empty() ? "" : ", ") + axis_name(ax);
        std::fprintf(stderr,
                     "meshless: warning: %s: all points lie on a %s (no extent along %s): the binning grid gives %s one "
                     "cell; the surface is the field's where it defines one off the data\n",
                     terminal_safe(name).c_str(), degenerate == 1 ? "plane" : "line", axes.c_str(), degenerate == 1 ? "that axis" : "those axes");
    }
    if (warn && in.grid.coarsened)
        std::fprintf(stderr,
                     "meshless: warning: %s: the binning rule asks for level %d (%lld cells); coarsened to level %d "
                     "(%lld cells) by --max-cells %lld / --max-level %d: stencils hold more points\n",
                     terminal_safe(name).c_str(), in.grid.rule_level,
                     static_cast<long long>(std::pow(std::ldexp(1.0, in.grid.rule_level) + 2, 3 - degenerate) * std::pow(3.0, degenerate)),
                     in.grid.level, static_cast<long long>(in.grid.cell_count()), static_cast<long long>(bp.max_cells), bp.max_level);
    // section 5.8: "pathological point distributions ... causing the tetrahedrization of a possibly large
    // number of points" (e.g. two far-apart clusters: the depth-first rule stops at the root)
    const std::int64_t most = warn ? largest_stencil(in.grid, in.bins) : 0;
    if (most > 20000 && double(most) > 0.25 * double(in.points.size()))
        std::fprintf(stderr,
                     "meshless: warning: %s: one 3x3x3 stencil of the level-%d binning grid holds %lld of the %zu points "
                     "(a pathological distribution for the binning rule, section 5.8): its Delaunay runs on one thread\n",
                     terminal_safe(name).c_str(), in.grid.level, static_cast<long long>(most), in.points.size());
    return in;
}

/// What generate writes and isosurface records (the same keys on both paths).
namespace {
/// The camera's frame: the binning grid with its border layer, where the regularisation points
/// lie and so the stencils' tetrahedra and the seeds, widened by how far Newton may move a seed
/// (max_travel cell diagonals, each seed's no longer than the binning cell's, kernels/stencil_seeds),
/// so that every point lies inside the recorded bounds: the points' box alone cut off surfaces
/// that bulge beyond the outermost samples (boreholes: up to 2 km). Degenerate axes keep the
/// points' extent.
std::array<Vec3, 2> frame_box(const BinningGrid& g, double max_travel) {
    const double pad = max_travel * g.diagonal() * (1 + 1e-6);
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = g.bounds[0][a];
        hi[a] = g.bounds[1][a];
        if (g.degenerate[static_cast<std::size_t>(a)]) continue;
        lo[a] = std::min(lo[a], g.origin[a]) - pad;
        hi[a] = std::max(hi[a], g.origin[a] + static_cast<double>(g.dims[static_cast<std::size_t>(a)]) * g.cell[a]) + pad;
    }
    return {Vec3{lo[0], lo[1], lo[2]}, Vec3{hi[0], hi[1], hi[2]}};
}
}  // namespace

StreamMeta scattered_meta(const ScatteredInput& in, double iso, int n, const std::string& producer) {
    // the frame allows for the default travel; a longer one widens it (widen_frame_for_travel), on
    // both paths the same way, so that isosurface and generate | project record the same bytes
    const double max_travel = kDefaultMaxTravel;
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
    const std::array<Vec3, 2> frame = frame_box(in.grid, max_travel);
    m.set("bounds_lo", triple(frame[0]));
    m.set("bounds_hi", triple(frame[1]));
    m.set("frame", "points");  // a box that holds every point, not the surface's: pictures frame the points
    m.set("volume_bounds_lo", triple(in.grid.bounds[0]));
    m.set("volume_bounds_hi", triple(in.grid.bounds[1]));
    m.set("frame_travel", max_travel);  // what the frame allows for
    m.set("frame_cell_diagonal", in.grid.diagonal());
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
                 "%s: %lld stencils (%lld crossed, largest %lld points), %lld regularisation points made on the fly "
                 "(%lld beyond --reg-gap), "
                 "%lld Delaunay failures, %lld tets (%lld owned, %lld with a NaN value), %lld triangles (%lld of zero area), "
                 "%lld seeds (n = %d, %zu per triangle)\n",
                 cmd, static_cast<long long>(s.stencils), static_cast<long long>(s.crossed_stencils),
                 static_cast<long long>(s.max_stencil_points), static_cast<long long>(s.regularisation_points),
                 static_cast<long long>(s.uncovered_regularisation),
                 static_cast<long long>(s.delaunay_failures), static_cast<long long>(s.tets), static_cast<long long>(s.owned_tets),
                 static_cast<long long>(s.nonfinite_tets), static_cast<long long>(s.triangles),
                 static_cast<long long>(s.zero_area_triangles), static_cast<long long>(s.seeds), n, lattice_size(n));
}

/// The default --samples of the scattered path, by measurement (20,000 samples of the
/// bucky volume, iso 100, rbf-grid field, 800 x 800 picture): the marching-tetrahedra triangles are
/// about the data's spacing, smaller than the multiblock cells of kDefaultLatticeN's measurement;
/// n = 1 (56 K points) leaves visible blotches at silhouettes where one disc stands for a whole
/// triangle, n = 2 (169 K points) gives a picture indistinguishable from n = 3 (339 K points) for
/// half the Newton work.
constexpr int kScatteredLatticeN = 2;

void add_scattered_options(Args& a) {
    add_samples_option(a, kScatteredLatticeN);
    add_binning_options(a);
}

double dedup_fraction(const Args& a) {
    const double f = parse_finite(a.get_or("dedup", "0"), "--dedup");
    if (f < 0 || f > 10) throw UsageError("--dedup: expected a fraction of the point radius in [0, 10]");
    return f;
}

}  // namespace

// ------------------------------------------------------------------ dispatch

bool scattered_invocation(const std::vector<std::string>& positionals, int argc, char** argv) {
    if (positionals.empty() || blocks_invocation(positionals)) return false;
    const std::string& p = positionals[0];
    const std::string e = lower_extension(p);
    // a .raw without the name convention is a volume when --dims describes it
    if (e == ".raw")
        for (int i = 2; i < argc; ++i) {
            const std::string tok = argv[i];
            if (tok == "--") break;
            if (tok == "--dims" || tok.rfind("--dims=", 0) == 0) return false;
        }
    if (looks_like_point_set(p)) return true;
    std::error_code ec;
    return e == ".ply" && std::filesystem::is_regular_file(p, ec) && !looks_like_volume(p);
}

// ------------------------------------------------------------------ isosurface POINTS

namespace {
int isosurface_scattered_run(const Args& a, Clock::time_point t_start, MpiSession* mpi);
}  // namespace

int isosurface_scattered(int argc, char** argv) {
    const auto t_start = Clock::now();
    Args a("isosurface", "POINTS --iso V -o out.ply [--png out.png] [--field mpu|rbf-grid|global-rbf|F.mlf] [--samples N] [options]",
           "Isosurface straight from scattered data (dissertation chapter 5): the points are binned in the grid\n"
           "of section 5.3 (octree, median of the depth-first levels, one surrounding layer of cells); a 3x3x3\n"
           "stencil marches over alternate cells: its points, plus one regularisation point with the field's value\n"
           "at the centre of each empty cell (made on the fly, never stored), are tetrahedralised by CGAL's Delaunay\n"
           "(section 5.4), marching tetrahedra contours the tetrahedra the stencil owns, the triangles are sampled\n"
           "on a barycentric lattice of N(N+1)/2 interior points, and every sample is projected onto the field's\n"
           "isosurface by safeguarded Newton iteration (section 5.6), of the MPU field (section 5.5) unless\n"
           "--field names another. Writes an oriented point set (binary PLY: x y z nx ny nz radius value, or\n"
           ".vtp) and/or a splatted PNG.\n"
           "POINTS: CSV/TSV/text, PLY, VTP, raw float32 records, .npy (see meshless info).");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "point set output: .ply or .vtp; '-' = stdout")
        .option("png", "", "FILE", "also render the points to this PNG");
    add_geometry_format_option(a);
    add_ply_color_option(a);
    add_scattered_options(a);
    a.option("dedup", "", "F", "remove points closer than F x their radius to an earlier point (overlapping stencils; 0 = keep all)", "0");
    add_newton_options(a);
    add_field_options(a, /*with_coverage=*/false, kPointsFieldDefault);
    add_quiet_option(a);
    add_camera_options(a);
    add_color_options(a);
    a.positionals(1, 1u << 20);
    a.epilog("examples: meshless sample ../shared/data/bucky/Bucky_32x32x32_uint8.raw -n 20000 -o bucky.ply && meshless isosurface bucky.ply --iso 100 -o b.ply --png b.png --stats\n"
             "pipes:    meshless fit POINTS -o f.mlf && meshless generate POINTS --iso V | meshless project --field f.mlf | meshless splat -o img.png\n");
    a.input_variant("scattered points");
    if (!a.parse(argc, argv, 2)) return 0;
    // under mpirun: the stencil rows are dealt to the ranks on request, rank 0 writes (stream/stencil_ranks.hpp)
    std::unique_ptr<MpiSession> mpi;
    if (launched_world_size() > 1) mpi = std::make_unique<MpiSession>(&argc, &argv);
    try {
        return isosurface_scattered_run(a, t_start, mpi.get());
    } catch (const std::exception& e) {
        if (!mpi) throw;
        // one failing rank ends the job: nothing is renamed into place, every rank exits non-zero
        const int code = exit_code(e);
        if (code != kExitOk)
            std::fprintf(stderr, "meshless isosurface (rank %d of %d): %s\n", mpi->rank(), mpi->size(), error_message(e).c_str());
        mpi->abort(code);
    }
}

namespace {

int isosurface_scattered_run(const Args& a, Clock::time_point t_start, MpiSession* mpi) {
    const bool root = !mpi || mpi->rank() == 0;
    const int ranks = mpi ? mpi->size() : 1;
    const double iso = parse_finite(a.require("iso"), "--iso");
    const auto out = a.get("output");
    const auto png = a.get("png");
    if (!out && !png) throw UsageError("nothing to write: give -o FILE and/or --png FILE");
    if (out) geometry_output_format(a, *out, kPointsWhat);
    if (png) require_output_extension(*png, ".png", "--png", "a PNG image");
    if (out && png && *out == *png && (*out == "-" || !is_streaming_output(*out)))
        throw UsageError("-o and --png name the same output '" + *out + "'");
    const int n = lattice_n(a, kScatteredLatticeN);
    const FieldProjectParams np = newton_params(a);
    (void)binning_params(a);
    const double dedup = dedup_fraction(a);
    RenderSettings rs = render_settings(a);
    const ColorChoice cc = color_choice(a);
    if (cc.request == ColorRequest::block) throw UsageError("scattered points have no blocks; --color block needs multiblock input");
    const int nthreads = threads(a);
    if (!field_file_arg(a)) (void)field_params(a);  // option errors before any reading

    ScatteredInput in = read_scattered(a, root);
    apply_color(rs, color_by(cc, ColorBy::none), cc, cc.range ? *cc.range : std::array<double, 2>{iso, iso});
    const bool crossed = iso_in_range(in, iso);
    if (!crossed && root) warn_if_iso_outside(iso, in.points.value_range(), in.source);
    StreamMeta meta = scattered_meta(in, iso, n, a.command_line());
    widen_frame_for_travel(meta, np.seed_max_travel);

    // the field: only when the isovalue is within the data (an empty output needs none)
    // under mpirun the ranks share the mpu field's local fits (every rank ends with the whole field)
    std::optional<FitShare> share;
    if (mpi)
        share = FitShare{mpi->rank(), mpi->size(), [mpi](std::span<const std::byte> mine) { return mpi->allgather(mine); }};
    double field_seconds = 0;
    BuiltField field = build_field_and_coverage(a, in, crossed, field_seconds, share ? &*share : nullptr);
    const std::string field_name = field.field ? field.field->name() : field_kind_arg(a);
    meta.set("projection", "newton");
    meta.set("field", field_name);
    meta.set("tolerance", np.seed_tolerance);

    const StencilGrid sg(in.grid.dims);
    std::optional<StencilSeedStage> seed;
    std::optional<FieldProjectStage> project;
    if (mpi) {
        std::optional<MpiChannel> channel;
        if (field.field) channel.emplace(*mpi);
        std::optional<StencilInput> sin;
        if (field.field) sin.emplace(StencilInput{in.grid, in.bins, std::span<const Vec3>(in.points.pos),
                                                 std::span<const double>(in.points.value), *field.field, in.coverage.get()});
        StencilRankResult rr;
        std::optional<DedupSink> dd;
        std::size_t points = 0;
        if (root) {
            IsoSplatResult unused;
            points = run_to_outputs(geometry_output(a, kPointsWhat), png, meta, rs, nthreads, [&](const Stage*, Sink& out_sink) {
                if (dedup > 0) dd.emplace(out_sink, dedup, 0.1 * in.grid.diagonal());
                Sink& sink = dd ? static_cast<Sink&>(*dd) : out_sink;
                // the deal's thread failing leaves the other ranks waiting for rows: end the job
                const auto deal_failed = [mpi](std::exception_ptr e) {
                    try {
                        std::rethrow_exception(e);
                    } catch (const std::exception& x) {
                        std::fprintf(stderr, "meshless isosurface (rank 0 of %d): %s\n", mpi->size(), error_message(x).c_str());
                        mpi->abort(exit_code(x));
                    } catch (...) {
                        mpi->abort(kExitInternal);
                    }
                };
                if (field.field) rr = run_stencils_rank(*sin, iso, n, np, 0, ranks, *channel, &sink, {nthreads}, deal_failed);
                else sink.finish();
                return IsoSplatResult{};
            }, unused, /*parallel_draw=*/false, /*with_blocks=*/false);
        } else if (field.field) {
            rr = run_stencils_rank(*sin, iso, n, np, mpi->rank(), ranks, *channel, nullptr, {nthreads});
        }
        auto v = rr.seeds.as_array();
        const FieldNewtonStats& ns = rr.newton;
        std::vector<std::int64_t> all(v.begin(), v.end());
        for (std::int64_t x : {ns.input, ns.converged, ns.flat, ns.too_far, ns.not_converged, ns.stalled, ns.nonfinite, ns.evaluations})
            all.push_back(x);
        const std::vector<std::int64_t> sums = mpi->sum_to_root(all);
        if (root && a.has("stats")) {
            std::array<std::int64_t, StencilSeedStats::kCounters> sv{};
            std::copy(sums.begin(), sums.begin() + StencilSeedStats::kCounters, sv.begin());
            sv[StencilSeedStats::kMaxIndex] = v[StencilSeedStats::kMaxIndex];  // (rank 0's)
            print_scattered_stats("isosurface", in, StencilSeedStats::from_array(sv), n);
            FieldNewtonStats tot;
            const std::size_t k = StencilSeedStats::kCounters;
            tot.input = sums[k]; tot.converged = sums[k + 1]; tot.flat = sums[k + 2]; tot.too_far = sums[k + 3];
            tot.not_converged = sums[k + 4]; tot.stalled = sums[k + 5]; tot.nonfinite = sums[k + 6]; tot.evaluations = sums[k + 7];
            print_newton_stats("isosurface", field_name, np, tot, 0.0);
            std::string dealt;
            for (std::size_t r = 0; r < rr.rows_per_rank.size(); ++r)
                dealt += (r ? " / " : "") + std::to_string(rr.rows_per_rank[r]);
            std::fprintf(stderr, "isosurface: %zu points over %d ranks x %d thread(s); stencil rows dealt on request: %s; time: read %.3f s, "
                         "octree + binning %.3f s, coverage %.3f s and field %.3f s side by side, total %.3f s (rank 0)\n",
                         points, ranks, nthreads, dealt.empty() ? "none" : dealt.c_str(), in.read_seconds, in.octree_seconds,
                         in.coverage_seconds, field_seconds, since(t_start));
        }
        return 0;
    }

    std::optional<DedupSink> dedup_sink;
    if (dedup > 0) meta.set("dedup", dedup);
    IsoSplatResult unused;
    const auto t0 = Clock::now();
    const std::size_t points = run_to_outputs(geometry_output(a, kPointsWhat), png, meta, rs, nthreads, [&](const Stage* draw, Sink& out_sink) {
        const auto g0 = Clock::now();
        // --dedup: the removal runs in sequence order on the sink side (the picture is then drawn there too)
        if (dedup > 0) dedup_sink.emplace(out_sink, dedup, 0.1 * in.grid.diagonal());
        Sink& sink = dedup_sink ? static_cast<Sink&>(*dedup_sink) : out_sink;
        if (!field.field) {
            RecordVectorSource empty(std::vector<PointRecord>{});
            const Stage* stages[] = {draw};
            run_pipeline(empty, std::span<const Stage* const>(stages, draw ? 1 : 0), sink, {nthreads});
        } else {
            StencilSource source(sg);
            seed.emplace(StencilInput{in.grid, in.bins, in.points.pos, in.points.value, *field.field, in.coverage.get()}, iso, n);
            project.emplace(*field.field, iso, np);
            // the stencils as the source hands them out, counted ahead of seeding
            ProgressMeter meter = ProgressMeter::of(a, "stencils", static_cast<double>(sg.total()));
            const ProgressStage progress([&](double k) { meter.add(k); }, work_units);
            const Stage* stages[] = {&progress, &*seed, &*project, draw};
            run_pipeline(source, std::span<const Stage* const>(stages, draw ? 4 : 3), sink, {nthreads});
        }
        IsoSplatResult r;
        r.seconds = since(g0);
        return r;
    }, unused, /*parallel_draw=*/dedup == 0, /*with_blocks=*/false);
    const double graph_seconds = since(t0);
    if (project) {
        const FieldNewtonStats ns = project->stats();
        if (ns.input > 0 && 2 * ns.converged < ns.input)
            std::fprintf(stderr,
                         "meshless: warning: %s: %lld of %lld seeds did not converge onto the %s field's isosurface (too far %lld, "
                         "non-finite %lld): the field does not resolve this point distribution there\n",
                         terminal_safe(in.source).c_str(), static_cast<long long>(ns.dropped()), static_cast<long long>(ns.input), field_name.c_str(),
                         static_cast<long long>(ns.too_far), static_cast<long long>(ns.nonfinite));
    }

    if (a.has("stats")) {
        const char* cmd = "isosurface";
        const StencilSeedStats s = seed ? seed->stats() : StencilSeedStats{};
        print_scattered_stats(cmd, in, s, n);
        if (project) print_newton_stats(cmd, field_name, np, project->stats(), project->busy_seconds());
        if (dedup_sink)
            std::fprintf(stderr, "%s: --dedup %g removed %lld near-duplicate points\n", cmd, dedup,
                         static_cast<long long>(dedup_sink->removed()));
        std::fprintf(stderr,
                     "%s: %zu points; time: read %.3f s, octree + binning %.3f s, coverage %.3f s and field %.3f s side by side, regularisation %.3f s busy, "
                     "isosurface (stencils + Delaunay + seeds + Newton + output) %.3f s (busy: stencils %.3f s of which "
                     "Delaunay %.3f s, Newton %.3f s over %d thread(s)), total %.3f s\n",
                     cmd, points, in.read_seconds, in.octree_seconds, in.coverage_seconds, field_seconds, 1e-9 * double(s.regularisation_ns), graph_seconds,
                     seed ? seed->busy_seconds() : 0.0, 1e-9 * double(s.delaunay_ns), project ? project->busy_seconds() : 0.0,
                     nthreads, since(t_start));
    }
    return 0;
}

}  // namespace

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
    add_field_options(a, /*with_coverage=*/false, kPointsFieldDefault);
    a.positionals(1, 1u << 20);
    a.epilog("example: meshless fit pts.ply -o f.mlf && meshless generate pts.ply --iso 0.5 --field f.mlf | meshless project --field f.mlf | meshless splat -o img.png\n");
    a.input_variant("scattered points");
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = parse_finite(a.require("iso"), "--iso");
    const int n = lattice_n(a, kScatteredLatticeN);
    (void)binning_params(a);
    const int nthreads = threads(a);
    if (!field_file_arg(a)) (void)field_params(a);
    const auto t0 = Clock::now();
    BinaryStreamOutput out(a.get_or("output", "-"), "a seed stream");
    ScatteredInput in = read_scattered(a);
    const bool crossed = iso_in_range(in, iso);
    if (!crossed) warn_if_iso_outside(iso, in.points.value_range(), in.source);
    double field_seconds = 0;
    BuiltField field = build_field_and_coverage(a, in, crossed, field_seconds);
    StreamSink sink(out.f, out.name, RecordKind::seed, scattered_meta(in, iso, n, a.command_line()), a.has("compress"));
    std::optional<StencilSeedStage> seed;
    if (field.field) {
        StencilSource source{StencilGrid(in.grid.dims)};
        seed.emplace(StencilInput{in.grid, in.bins, in.points.pos, in.points.value, *field.field, in.coverage.get()}, iso, n);
        const Stage* stages[] = {&*seed};
        run_pipeline(source, stages, sink, {nthreads});
    } else {
        RecordVectorSource empty(std::vector<PointRecord>{});
        run_pipeline(empty, {}, sink, {nthreads});
    }
    out.commit();
    if (a.has("stats")) {
        print_scattered_stats("generate", in, seed ? seed->stats() : StencilSeedStats{}, n);
        std::fprintf(stderr, "generate: read %.3f s, octree + binning %.3f s, coverage %.3f s and field %.3f s side by side, total %.3f s\n",
                     in.read_seconds, in.octree_seconds, in.coverage_seconds, field_seconds, since(t0));
    }
    return 0;
}

}  // namespace meshless::cli
