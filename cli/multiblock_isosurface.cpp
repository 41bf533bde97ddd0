#include "cli/multiblock_isosurface.hpp"
#include "cli/progress_meter.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "formats/binary_stream_output.hpp"
#include "cli/field_cli.hpp"
#include "stream/mpi_session.hpp"
#include "cli/point_set_cli.hpp"
#include "formats/input_kind.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/barycentric_lattice.hpp"
#include "kernels/errors.hpp"
#include "stream/block_isosurface_job.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/sample_stream_projection.hpp"
#include "stream/stream_endpoints.hpp"
#include "stream/seconds_since.hpp"

namespace meshless::cli {

// ------------------------------------------------------------------ options

void add_samples_option(Args& a, int default_n) {
    a.option("samples", "", "N",
             "seeds per marching-cubes triangle: the barycentric lattice of N(N+1)/2 interior points (section 4.4)",
             std::to_string(default_n));
}

int lattice_n(const Args& a, int default_n) {
    const long long n = a.get_int_or("samples", default_n);
    if (n < 1 || n > kMaxLatticeN) throw UsageError("--samples: expected 1.." + std::to_string(kMaxLatticeN) + ", got " + std::to_string(n));
    return static_cast<int>(n);
}

void add_newton_options(Args& a) {
    a.option("tolerance", "", "T", "Newton: a seed has converged when its next step is below T x its cell's diagonal", "0.01")
        .option("max-iterations", "", "K", "Newton: field evaluations per seed (halvings included) before it is dropped", "20")
        .option("max-travel", "", "F", "Newton: drop a seed that would move farther than F cell diagonals (0 = no limit)", "2");
    static_assert(kDefaultMaxTravel == 2, "the --max-travel default above");
}

FieldProjectParams newton_params(const Args& a) {
    FieldProjectParams p;
    p.seed_tolerance = parse_finite(a.get_or("tolerance", "0.01"), "--tolerance");
    if (!(p.seed_tolerance > 0) || p.seed_tolerance > 1) throw UsageError("--tolerance: expected a fraction of the cell diagonal in (0, 1]");
    const long long k = a.get_int_or("max-iterations", 20);
    if (k < 1 || k > 1000) throw UsageError("--max-iterations: expected 1..1000");
    p.newton.max_iterations = static_cast<int>(k);
    const double travel = parse_finite(a.get_or("max-travel", a.default_of("max-travel")), "--max-travel");
    if (travel < 0) throw UsageError("--max-travel: expected a number of cell diagonals >= 0");
    p.seed_max_travel = travel == 0 ? std::numeric_limits<double>::infinity() : travel;
    return p;
}

std::optional<std::string> point_outputs_png(const Args& a) {
    const auto out = a.get("output");
    const auto png = a.get("png");
    if (!out && !png) throw UsageError("nothing to write: give -o FILE and/or --png FILE");
    if (out) geometry_output_format(a, *out, "an oriented point set");
    if (png) require_output_extension(*png, ".png", "--png", "a PNG image");
    if (out && png && *out == *png && (*out == "-" || !is_streaming_output(*out)))
        throw UsageError("-o and --png name the same output '" + *out + "'");
    return png;
}

namespace {

using Clock = std::chrono::steady_clock;

// ------------------------------------------------------------------ inputs

using BlockInput = BlockIsosurfaceInput;

BlockInput read_blocks(const Args& a, double iso) {
    if (a.positional().empty()) throw UsageError("missing BLOCKS argument (see meshless " + a.command() + " --help)");
    return read_block_input(a.positional(), point_set_options(a), joined_names(a.positional()), iso);
}

}  // namespace

// ------------------------------------------------------------------ dispatch

std::vector<std::string> scan_positionals(int argc, char** argv, int first, std::initializer_list<const Args*> parsers) {
    std::vector<std::string> pos;
    bool only = false;
    for (int i = first; i < argc; ++i) {
        const std::string tok = argv[i];
        if (only || tok == "-" || tok.size() < 2 || tok[0] != '-' ||
            std::isdigit(static_cast<unsigned char>(tok[1])) || tok[1] == '.') {
            pos.push_back(tok);
            continue;
        }
        if (tok == "--") {
            only = true;
            continue;
        }
        if (tok.find('=') != std::string::npos) continue;
        for (const Args* p : parsers)
            if (p->takes_value(tok)) {
                ++i;
                break;
            }
    }
    return pos;
}

bool project_seeds_invocation(int argc, char** argv) {
    for (int i = 2; i < argc; ++i) {
        const std::string tok = argv[i];
        if (tok == "--") return false;
        if (tok == "--field" || tok.rfind("--field=", 0) == 0) return true;
    }
    return false;
}

// ------------------------------------------------------------------ isosurface BLOCKS

int isosurface_blocks(int argc, char** argv) {
    const auto t_start = Clock::now();
    Args a("isosurface", "BLOCKS... --iso V -o out.ply [--png out.png] [--field rbf-grid|mpu|global-rbf] [--samples N] [options]",
           "Crack-free isosurface of overlapping multiblock grids and AMR hierarchies (dissertation chapter 4):\n"
           "one continuous meshless field is built over every block's valid nodes (grid connectivity ignored,\n"
           "section 4.3); each block's marching-cubes triangles (cells with a blanked/NaN corner and collapsed or\n"
           "inverted cells skipped and counted) are sampled on a barycentric lattice of N(N+1)/2 interior points,\n"
           "and every sample is projected onto the field's isosurface by safeguarded Newton iteration (section\n"
           "4.4). Writes an oriented point set (binary PLY: x y z nx ny nz radius value block; radius\n"
           "2(1 + d/l) sqrt(2A/(pi N(N+1))), block = the block the point was seeded in) and/or a splatted PNG.\n"
           "BLOCKS: PLOT3D xyz (+ q/function file), .vts pieces, .vtm/.vthb (see meshless info).");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "point set output: .ply or .vtp (ParaView: vertex cells, Normals, radius, value, block); '-' = stdout")
        .option("png", "", "FILE", "also render the points to this PNG");
    add_geometry_format_option(a);
    add_ply_color_option(a);
    add_samples_option(a);
    add_newton_options(a);
    add_field_options(a, /*with_coverage=*/false);
    add_quiet_option(a);
    add_camera_options(a);
    add_color_options(a);
    a.positionals(1, 1u << 20);
    a.epilog("examples: meshless isosurface ../shared/data/plot3d/combxyz.bin --iso 0.4 -o comb.ply --png comb.png --stats\n"
             "          meshless isosurface multicomb_0.vts multicomb_1.vts multicomb_2.vts --iso 0.4 -o mc.ply\n"
             "pipes:    meshless generate BLOCKS --iso V | meshless project --field mpu BLOCKS | meshless write -o out.ply\n");
    a.input_variant("multiblock grids");
    if (!a.parse(argc, argv, 2)) return 0;
    if (launched_world_size() > 1)
        throw UsageError("multiblock inputs are not split over MPI ranks: run meshless isosurface BLOCKS... without mpirun");
    IsosurfaceJob j;
    j.started = t_start;
    j.iso = single_iso(a, "multiblock grids");
    j.png = point_outputs_png(a);
    j.n = lattice_n(a);
    j.np = newton_params(a);
    j.rs = render_settings(a);
    const ColorChoice cc = color_choice(a);
    j.threads = threads(a);

    if (!field_file_arg(a)) (void)field_params(a);  // option errors before any reading
    BlockInput in = read_blocks(a, j.iso);
    // Colours: every point carries the isovalue, so the default is the uniform surface colour;
    // --color block colours by the block a point was seeded in.
    apply_color(j.rs, color_by(cc, ColorBy::none), cc, cc.range ? *cc.range : std::array<double, 2>{j.iso, j.iso});
    j.rs.legend_blocks = static_cast<std::uint32_t>(in.mb.blocks.size());
    warn_if_no_block_cell_crossed(stderr, in, j.iso);
    // the field: only when some cell is crossed; without one, its name as --field gives it
    const IsosurfaceField f =
        fit_block_field(in, j.iso, j.n, a.command_line(), j.np, a.get_or("field", "rbf-grid"), [&](const PointSet& p) { return build_field(a, p); });
    j.out = geometry_output(a, "an oriented point set");
    j.progress = progress_counter(a);
    if (a.has("stats")) j.stats = stderr;
    run_block_isosurface_job(j, in, f, "isosurface");
    return 0;
}

// ------------------------------------------------------------------ generate BLOCKS

int generate_blocks(int argc, char** argv) {
    Args a("generate", "BLOCKS... --iso V [--samples N] [-o FILE|-]",
           "The seeds of the multiblock/AMR isosurface (dissertation section 4.4): per block, per hexahedral cell,\n"
           "the marching-cubes triangles, sampled on the barycentric lattice of N(N+1)/2 interior points, written\n"
           "as a binary seed stream (stdout by default) for `meshless project --field KIND BLOCKS...`.");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "stream output, '-' = stdout", "-")
        .flag("compress", "zstd-compress the stream's DATA frames")
        .flag("stats", "print cell, triangle and seed counts and timing to stderr");
    add_samples_option(a);
    add_point_set_options(a, /*with_endian=*/true);
    add_thread_option(a);
    a.positionals(1, 1u << 20);
    a.epilog("example: meshless generate combxyz.bin --iso 0.4 | meshless project --field rbf-grid combxyz.bin | meshless write -o c.ply\n");
    a.input_variant("multiblock grids");
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = single_iso(a, "multiblock grids");
    const int n = lattice_n(a);
    const int nthreads = threads(a);
    const auto t0 = Clock::now();
    BinaryStreamOutput out(a.get_or("output", "-"), "a seed stream");
    BlockInput in = read_blocks(a, iso);
    warn_if_no_block_cell_crossed(stderr, in, iso);
    StreamSink sink(out.f, out.name, RecordKind::seed, block_isosurface_meta(in, iso, n, a.command_line()), a.has("compress"));
    const BlockSeedStats seeds = generate_block_seeds(in, iso, n, sink, {nthreads});
    out.commit();
    if (a.has("stats")) print_block_generate_stats(stderr, "generate", in, seeds, n, seconds_since(t0));
    return 0;
}

// ------------------------------------------------------------------ project --field

int project_seeds(int argc, char** argv) {
    Args a("project", "--field KIND DATA... | --field FILE.mlf [--input FILE|-] [-o FILE|-]",
           "Projects a seed stream (from `meshless generate BLOCKS...`) onto the isosurface of the continuous\n"
           "meshless field built from DATA (or loaded from --field FILE.mlf, see meshless fit) (dissertation sections 4.3-4.4): safeguarded Newton iteration per\n"
           "seed; writes a point stream whose points carry the id of the block they were seeded in. Give the\n"
           "same BLOCKS as DATA to get the bytes of the in-process `meshless isosurface BLOCKS...`.");
    a.option("input", "i", "FILE", "seed stream, '-' = stdin", "-")
        .option("iso", "", "V", "isovalue (default: the one recorded by generate)")
        .option("output", "o", "FILE", "point stream output, '-' = stdout", "-")
        .flag("compress", "zstd-compress the stream's DATA frames");
    add_newton_options(a);
    add_field_options(a, /*with_coverage=*/false);
    a.positionals(0, 1u << 20);
    if (!a.parse(argc, argv, 2)) return 0;
    if (!field_file_arg(a) && a.positional().empty())
        throw UsageError("missing DATA argument: the files the field is built from, or --field FILE.mlf (see meshless project --help)");
    const FieldProjectParams np = newton_params(a);
    const int nthreads = threads(a);
    const auto t0 = Clock::now();
    InputFile in(a.get_or("input", "-"));
    StreamReader reader(in.f, in.name);
    require_seed_stream(reader, in.name);
    reader.read_meta();
    const double iso = stream_iso(a, reader.meta());
    BinaryStreamOutput out(a.get_or("output", "-"), "a point stream");
    const auto t1 = Clock::now();
    BuiltField field = field_file_arg(a) && a.positional().empty() ? load_field_arg(a)
                                                                   : build_field(a, read_points_arg(a));
    const double field_seconds = seconds_since(t1);
    const SeedProjectionResult pr = project_seed_stream(reader, *field.field, iso, np, out.f, out.name, a.has("compress"), nthreads);
    out.commit();
    if (a.has("stats")) {
        print_newton_stats(stderr, "project", field.field->name(), np, pr.stats, pr.busy_seconds);
        std::fprintf(stderr, "project: field %.3f s, total %.3f s\n", field_seconds, seconds_since(t0));
    }
    return 0;
}

}  // namespace meshless::cli
