#include "cli/scattered_isosurface.hpp"
#include "cli/progress_meter.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "formats/binary_stream_output.hpp"
#include "cli/field_cli.hpp"
#include "stream/mpi_session.hpp"
#include "cli/multiblock_isosurface.hpp"
#include "stream/scattered_isosurface.hpp"
#include "stream/scattered_isosurface_job.hpp"
#include "stream/scattered_isosurface_mpi.hpp"
#include "stream/scattered_store_isosurface.hpp"
#include "formats/input_kind.hpp"
#include "formats/point_store.hpp"
#include "stream/available_memory.hpp"
#include "cli/point_set_cli.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "kernels/scattered_binning_grid.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/stencil_source.hpp"
#include "stream/stream_endpoints.hpp"
#include "stream/seconds_since.hpp"

namespace meshless::cli {

namespace {

using Clock = std::chrono::steady_clock;

void add_binning_options(Args& a) {
    a.option("max-cells", "", "N", "cap on the binning grid's cells (section 5.3), 27..2^31 (4 bytes a cell must fit in "
                                   "memory): a finer grid is coarsened, with a warning",
             std::to_string(BinningGridParams{}.max_cells))
        .option("max-level", "", "L", "cap on the binning level l_b (2^L cells per axis), 0..12", std::to_string(BinningGridParams{}.max_level))
        .option("reg-gap", "", "F",
                "a regularisation point farther than F x the local point spacing (8th-neighbour distance) from the data "
                "gets no value (no surface where no data is); 0 = every empty cell gets the field's value", "4");
}

double reg_gap(const Args& a) {
    const double f = parse_finite(a.get_or("reg-gap", "4"), "--reg-gap");
    if (f < 0) throw UsageError("--reg-gap: expected a factor >= 0");
    return f;
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

using ScatteredInput = ScatteredIsosurfaceInput;

/// The input warnings (binning, the plan) as `meshless: warning: SUBJECT: WHAT` lines on stderr.
InputWarning stderr_warning() {
    return [](const std::string& subject, const std::string& what) {
        std::fprintf(stderr, "meshless: warning: %s: %s\n", terminal_safe(subject).c_str(), what.c_str());
    };
}

ScatteredInput read_scattered(const Args& a, bool warn = true) {
    if (a.positional().empty()) throw UsageError("missing POINTS argument (see meshless " + a.command() + " --help)");
    const BinningGridParams bp = binning_params(a);
    const auto t0 = Clock::now();
    PointSet points = read_points_arg(a);
    const double read_seconds = seconds_since(t0);
    ScatteredInput in = bin_scattered_points(std::move(points), joined_names(a.positional()), a.positional()[0], bp, reg_gap(a),
                                             warn ? stderr_warning() : InputWarning{});
    in.read_seconds = read_seconds;
    return in;
}

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
    bool raw_dims = false;  // a .raw given --dims is a volume
    for (int i = 2; i < argc; ++i) {
        const std::string tok = argv[i];
        if (tok == "--") break;
        if (tok == "--dims" || tok.rfind("--dims=", 0) == 0) raw_dims = true;
    }
    return names_scattered_points(positionals, raw_dims);
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
           "POINTS: CSV/TSV/text, PLY, VTP, VTU nodes, raw float32 records, .npy (see meshless info), or a point store (.mlc,\n"
           "made by meshless convert): with the mpu field and a limited --max-travel it runs in z slabs within\n"
           "--memory, the bytes of the store read whole for any budget (a PLY of the same points gives the same\n"
           "samples in another order). Under mpirun each rank takes its own z layers of a store and reads only\n"
           "the points they need; other points are read by every rank, which builds the whole field.");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "point set output: .ply or .vtp; '-' = stdout")
        .option("png", "", "FILE", "also render the points to this PNG");
    add_fail_empty_option(a);
    add_geometry_format_option(a);
    add_ply_color_option(a);
    add_scattered_options(a);
    a.option("dedup", "", "F", "remove points closer than F x their radius to an earlier point (overlapping stencils; 0 = keep all)", "0");
    add_newton_options(a);
    add_field_options(a, /*with_coverage=*/false, kPointsFieldDefault);
    add_quiet_option(a);
    add_camera_options(a);
    add_color_options(a);
    a.option("memory", "", "BYTES",
             "a point store (.mlc) with the mpu field and --max-travel > 0: the budget its slabs are sized "
             "to, e.g. 512M, 2G, each rank's under mpirun (default: the memory this process may use, shared by the ranks "
             "on a machine); the output does not depend on it. Budgets "
             "near the least that runs make many thin slabs, each a rebuild of its overlap: see --stats")
        .validate([](const std::string& v) { (void)parse_memory_size(v); });
    a.positionals(1, 1u << 20);
    a.epilog("examples: meshless sample ../shared/data/bucky/Bucky_32x32x32_uint8.raw -n 20000 -o bucky.ply && meshless isosurface bucky.ply --iso 100 -o b.ply --png b.png --stats\n"
             "          meshless convert bucky.ply -o bucky.mlc && meshless isosurface bucky.mlc --iso 100 -o b.ply --memory 64M\n"
             "mpirun:   mpirun -np 4 meshless isosurface bucky.mlc --iso 100 -o b.ply --memory 64M --threads 1\n"
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
        return end_mpi_run(*mpi, "isosurface", e);
    }
}

namespace {

/// What the scattered isosurface prepares before its graph runs (options checked, data read and
/// binned, field built).
struct ScatteredJob {
    IsosurfaceJob job;
    double dedup = 0;
    ScatteredInput in;
    IsosurfaceField f;  ///< the field, its name and time, the metadata
    bool warned = false;  ///< a line already said the isovalue lies outside the data
};

/// The options of the job, checked before any reading; the colour choice is returned.
ColorChoice parse_scattered_options(const Args& a, Clock::time_point t_start, ScatteredJob& s) {
    IsosurfaceJob& j = s.job;
    j.started = t_start;
    j.iso = single_iso(a, "scattered points");
    j.png = point_outputs_png(a);
    j.n = lattice_n(a, kScatteredLatticeN);
    j.np = newton_params(a);
    (void)binning_params(a);
    s.dedup = dedup_fraction(a);
    j.rs = render_settings(a);
    const ColorChoice cc = color_choice(a);
    if (cc.request == ColorRequest::block) throw UsageError("scattered points have no blocks; --color block needs multiblock input");
    j.threads = threads(a);
    if (!field_file_arg(a)) (void)field_params(a);  // option errors before any reading
    j.progress = progress_counter(a);
    if (a.has("stats")) j.stats = stderr;
    return cc;
}

ScatteredJob prepare_scattered(const Args& a, Clock::time_point t_start, MpiSession* mpi) {
    const bool root = !mpi || mpi->rank() == 0;
    ScatteredJob s;
    IsosurfaceJob& j = s.job;
    const ColorChoice cc = parse_scattered_options(a, t_start, s);
    s.in = read_scattered(a, root);
    apply_color(j.rs, color_by(cc, ColorBy::none), cc, cc.range ? *cc.range : std::array<double, 2>{j.iso, j.iso});
    if (!s.in.crosses(j.iso) && root) s.warned = warn_if_iso_outside(j.iso, s.in.points.value_range(), s.in.source);
    // under mpirun the ranks share the mpu field's local fits (every rank ends with the whole field)
    std::optional<FitShare> share;
    if (mpi) share = mpi_fit_share(*mpi);
    s.f = fit_scattered_field(s.in, j.iso, j.n, a.command_line(), &j.np, j.threads, field_kind_arg(a),
                              [&] { return build_field(a, s.in.points, {}, share ? &*share : nullptr); });
    return s;
}

/// A point store (.mlc) with the mpu field: slab by slab within --memory (stream/scattered_store_isosurface.hpp).
bool runs_store_slabs(const Args& a) {
    if (a.positional().size() != 1 || field_file_arg(a) || !is_point_store(a.positional()[0])) return false;
    if (parse_finite(a.get_or("max-travel", a.default_of("max-travel")), "--max-travel") == 0) return false;  // (no slab bound: read whole)
    return field_kind_arg(a, kPointsFieldDefault) == "mpu";
}

int isosurface_scattered_store(const Args& a, Clock::time_point t_start, MpiSession* mpi) {
    const bool root = !mpi || mpi->rank() == 0;
    ScatteredJob s;
    IsosurfaceJob& j = s.job;
    const ColorChoice cc = parse_scattered_options(a, t_start, s);
    const FieldParams fp = field_params(a, kPointsFieldDefault);
    ScatteredStoreParams sp;
    // (under mpirun --memory is each rank's; by default the ranks on a machine share its memory)
    sp.memory_bytes = a.has("memory") ? parse_memory_size(*a.get("memory"))
                                      : available_memory() / static_cast<std::uint64_t>(mpi ? launched_local_size() : 1);
    sp.reg_gap = reg_gap(a);
    const std::string& path = a.positional()[0];
    const auto store = PointStore::open(path);
    // (every rank scans the store: the plan is what the whole set decides, the same on every rank)
    const ScatteredStorePlan plan = plan_scattered_store(*store, joined_names(a.positional()), binning_params(a),
                                                         root ? stderr_warning() : InputWarning{});
    apply_color(j.rs, color_by(cc, ColorBy::none), cc, cc.range ? *cc.range : std::array<double, 2>{j.iso, j.iso});
    const bool warned = root && !plan.crosses(j.iso) && warn_if_iso_outside(j.iso, plan.value_range, plan.source);
    j.out = geometry_output(a, kPointsWhat);
    if (mpi) {
        if (!root) j.progress = {};
        const std::size_t points = run_scattered_store_mpi_job(j, s.dedup, *mpi, *store, plan, fp, sp, a.command_line(), a.get("memory"), "isosurface");
        return root ? empty_result_exit(a, points, "points", j.iso, plan.source, warned) : 0;
    }
    const std::size_t points = run_scattered_store_job(j, s.dedup, *store, plan, fp, sp, a.command_line(), a.get("memory"), "isosurface");
    return empty_result_exit(a, points, "points", j.iso, plan.source, warned);
}

int isosurface_scattered_run(const Args& a, Clock::time_point t_start, MpiSession* mpi) {
    if (runs_store_slabs(a)) return isosurface_scattered_store(a, t_start, mpi);
    if (a.has("memory"))  // (a budget the run below cannot keep: say so rather than exceed it silently)
        std::fprintf(stderr, "meshless isosurface: warning: --memory bounds only a point store (.mlc) with the mpu field and "
                             "--max-travel > 0; these points and their field are held in memory whole\n");
    ScatteredJob s = prepare_scattered(a, t_start, mpi);
    s.job.out = geometry_output(a, kPointsWhat);
    if (mpi) {  // the deal's thread failing leaves the other ranks waiting for rows: end the job
        run_scattered_isosurface_mpi_job(s.job, s.dedup, *mpi, s.in, s.f, "isosurface",
                                         [mpi](std::exception_ptr e) { end_mpi_job(*mpi, "isosurface", e); });
        return 0;
    }
    const std::size_t points = run_scattered_isosurface_job(s.job, s.dedup, s.in, s.f, "isosurface");
    return empty_result_exit(a, points, "points", s.job.iso, s.in.source, s.warned);
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
    const double iso = single_iso(a, "scattered points");
    const int n = lattice_n(a, kScatteredLatticeN);
    (void)binning_params(a);
    const int nthreads = threads(a);
    if (!field_file_arg(a)) (void)field_params(a);
    const auto t0 = Clock::now();
    BinaryStreamOutput out(a.get_or("output", "-"), "a seed stream");
    ScatteredInput in = read_scattered(a);
    if (!in.crosses(iso)) warn_if_iso_outside(iso, in.points.value_range(), in.source);
    const IsosurfaceField f = fit_scattered_field(in, iso, n, a.command_line(), nullptr, nthreads, field_kind_arg(a),
                                                 [&] { return build_field(a, in.points); });
    StreamSink sink(out.f, out.name, RecordKind::seed, f.meta, a.has("compress"));
    const StencilSeedStats seeds = generate_scattered_seeds(in, f.field.field.get(), iso, n, sink, {nthreads});
    out.commit();
    if (a.has("stats")) print_scattered_generate_stats(stderr, "generate", in, seeds, n, {f.seconds, 0, seconds_since(t0)});
    return 0;
}

}  // namespace meshless::cli
