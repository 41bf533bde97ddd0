// meshless-bench: the benchmarks of dissertation §3.6 (accuracy, extraction speed and memory vs
// marching cubes and VTK Flying Edges, thread scaling, splat frame rates), out of core (brick
// stores, paradigms A and C, peak memory), the meshless fields, and whole processes as users run
// them (bench/bench_process.cpp). An executable of its own, never part of the
// `meshless` product. Thin: parses options and runs the sections in bench/bench_*.cpp.
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "cli/args.hpp"
#include "cli/errors.hpp"
#include "bench/bench_common.hpp"

namespace meshless::bench {

namespace {

namespace fs = std::filesystem;

using cli::Args;
using cli::UsageError;

/// Folder holding flying_edges.py: the source folder this executable was built from, else
/// ../../bench relative to the executable (build/bench/meshless-bench).
std::string default_bench_dir() {
    std::error_code ec;
    const fs::path src(MESHLESS_BENCH_SOURCE_DIR);
    if (fs::exists(src / "flying_edges.py", ec)) return src.string();
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path d = exe.parent_path().parent_path().parent_path() / "bench";
        if (fs::exists(d / "flying_edges.py", ec)) return d.string();
    }
    return "bench";
}

/// The `meshless` built beside this executable (build/cli/meshless), else the one on PATH.
std::string default_meshless() {
    std::error_code ec;
    const fs::path built(MESHLESS_BENCH_DEFAULT_MESHLESS);
    if (fs::exists(built, ec)) return built.string();
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path d = exe.parent_path().parent_path() / "cli" / "meshless";
        if (fs::exists(d, ec)) return d.string();
    }
    return "meshless";
}

// $MESHLESS_DATA, else ../shared/data from the working folder, else the one beside the repository
// this bench was built from (so a run from another folder still finds the real data sets)
std::string default_data_dir() {
    if (const char* e = std::getenv("MESHLESS_DATA"); e && *e) return e;
    std::error_code ec;
    if (fs::is_directory("../shared/data", ec)) return "../shared/data";
    const fs::path beside = fs::path(MESHLESS_BENCH_SOURCE_DIR).parent_path().parent_path() / "shared" / "data";
    if (fs::is_directory(beside, ec)) return beside.string();
    return "../shared/data";
}

}  // namespace

/// Args names its program "meshless COMMAND"; this executable is "meshless-bench".
std::string own_name(std::string text) {
    for (std::size_t p; (p = text.find("meshless bench")) != std::string::npos;) text.replace(p, 14, "meshless-bench");
    return text;
}

int bench_main(int argc, char** argv) {
    Args a("bench", "[accuracy|speed|threads|splat|ooc|fields|process|multiblock|render|scattered|hierarchy|python|all] [options]",
           "Benchmarks, printed as tables on stdout (progress on stderr); ratios are against baselines\n"
           "measured in the same run. Results are written to a file only with --markdown FILE.\n"
           "  accuracy  distance / normal / value errors of the projected points on analytic fields, coverage\n"
           "  speed     extraction time and memory: iso-splatting vs marching cubes vs VTK Flying Edges\n"
           "  threads   iso-splatting on 1 and 2 threads, identical output\n"
           "  splat     quad and EWA splat frame times, 36-frame turntable\n"
           "  ooc       brick stores: conversion MB/s and ratio, store vs in-memory throughput, paradigm A vs C\n"
           "            vs marching cubes, threads and MPI ranks, peak RSS on a 4.4 GB volume (minutes, GBs)\n"
           "  fields    meshless fields (rbf-grid, mpu, global-rbf): accuracy vs SciPy RBFInterpolator, linear\n"
           "            reproduction, Table 4.1 construction times, evaluation rate, 1M-point memory (minutes)\n"
           "  process   whole `meshless` processes as users run them on the lung-sized CT (LIDC2 x2): isosurface\n"
           "            vs VTK Flying Edges, pipes vs in-process, threads, paradigm A vs C, splat throughput and\n"
           "            peak RSS (best-of-N wall clock, RSS from wait4; a few minutes, ~1 GB in --work)\n"
           "  multiblock  split + isosurface from blocks on analytic fields in every multiblock / AMR layout:\n"
           "            coverage of the true isosurface, distance and normal errors vs the naive per-block MC's\n"
           "            cracks; Table 4.1 sets and the combustor at 1 and 2 threads; VTK per-block contour\n"
           "  render    volume rendering by ray casting: LIDC2 512x512 trilinear (1, 2 threads, transfer\n"
           "            functions, skipping on/off), scattered samples of it through the mpu field, PSNR vs the volume\n"
           "  scattered  isosurface from scattered points (analytic fields, uniform / clustered / layered,\n"
           "            10^4..10^6 points) against the truth and SciPy griddata, vtkDelaunay3D, vtkPointInterpolator in the\n"
           "            same run; Table 5.1 rebuilt from --stats; time, peak RSS, threads and MPI ranks up to 10^6 points\n"
           "  hierarchy cluster binary trees (chapter 6): silicium and head Tables 6.1-6.2, speed, threads,\n"
           "            LOD extraction rate, peak RSS, CBT LOD vs random subsample vs decimation (RMSE of the mpu field;\n"
           "            that part alone: hierarchy-rmse)\n"
           "  python    the Python module: equality with the CLI, peak RSS on an np.memmap volume, call overhead,\n"
           "            two threads vs two calls in sequence, Field vs SciPy RBFInterpolator (bench/python_module.py)\n"
           "  scale     the scattered isosurface of 10^5..3x10^6 LIDC2 samples (--sizes): in memory, from a point\n"
           "            store (.mlc) in one slab and within 2/3 of its memory (same bytes?), the VTK peer; the mpu and\n"
           "            rbf-grid fields' construction and one-core evaluation rate at each size; not in all\n"
           "  all       everything (the default; ooc only with --with-ooc or 16 GiB free in the scratch folder)");
    a.option("data", "", "DIR", "shared test data folder ($MESHLESS_DATA, else ../shared/data, else the one beside the source tree)")
        .option("reps", "", "N", "repetitions per isosurface (default 10); process: best of N runs (default 3)")
        .option("isovalues", "", "K", "isosurfaces per volume", "16")
        .option("markdown", "", "FILE", "also write the tables as markdown to FILE (nothing is written without it)")
        .option("bench-dir", "", "DIR", "folder holding flying_edges.py and rbf_reference.py (default: the source tree's bench/)")
        .option("python", "", "EXE", "Python interpreter with the vtk module (speed) and scipy (fields)", "/usr/bin/python3")
        .option("scratch", "", "DIR", "ooc: folder for its temporary stores (default: the system temp folder)")
        .option("meshless", "", "PATH", "the meshless executable the whole-process rows run (default: the one built beside this)")
        .option("work", "", "DIR", "process: cache folder for the lung-sized volume, its store and point sets, kept and "
                                   "reused (scattered, scale: their point sets) (default: a temporary folder, removed at the end)")
        .option("sizes", "", "N1,N2,...", "scattered: point counts of the accuracy part (default 10000,100000,1000000; --quick 3000); "
                                           "scale: the sizes (default 100000,1000000,3000000; --quick 20000)")
        .option("field", "", "NAME", "scattered: --field passed to `meshless isosurface` (default: the command's own)")
        .option("peer-timeout", "", "S", "scattered: seconds allowed per peer run (default 120; --quick 30)")
        .option("fields", "", "LIST", "scattered (a): analytic fields, e.g. sphere,gyroid,ml (default: those three)")
        .option("distributions", "", "LIST", "scattered (a): uniform,clustered,layered or a subset (default: all)")
        .option("parts", "", "LIST", "scattered: a (accuracy and peers), b (Table 5.1), c (scaling) or a subset (default: all)")
        .option("hardy-c", "", "C1,C2,...", "hierarchy-rmse: Hardy's c of the mpu fields relative to the bounding-box "
                                            "diagonal, one table per value (default: the field's own, 0.025)")
        .option("hardy-c-spacing", "", "K", "fields: cap every local fit's Hardy c at K x its point spacing (0: the global c; "
                                            "default: the field's own)")
        .option("sets", "", "LIST", "scale: ct (LIDC2 samples), clustered, layered (the gyroid at those positions) or a subset "
                                    "(default: ct)")
        .option("ranks", "", "LIST", "scale: also run each store under mpirun with these rank counts, e.g. 2,4 (1..64; "
                                     "default: none)")
        .flag("no-peers", "scattered: skip the SciPy / VTK peers")
        .flag("all-peers", "scattered: peers on every set and size (default: all up to 20,000 points, fewer above)")
        .flag("reuse-peers", "scattered: reuse the peer results an earlier run kept in --work (said in the output)")
        .flag("large", "process: also the 10^8-point splat row (3.2 GB of PLY in --work)")
        .flag("keep", "ooc: keep the scratch files (stores, the 4.4 GB volume's store)")
        .flag("with-ooc", "all: include the ooc section whatever the free space")
        .flag("quick", "smoke test: 2 reps, 4 isovalues, no large volumes (ooc: LIDC2 x1, no 4 GiB volume, no MPI; "
                       "fields: N = 1K, 10K, no 1M; process: LIDC2 x1, 1 isovalue, 10^4/10^5-point splats; scattered: 3,000 "
                       "points, sphere and gyroid, peers on the sphere's uniform set, 2,000-point Table 5.1 sets, no MPI)");
    a.epilog("examples: meshless-bench process --work /tmp/mb-cache --markdown /tmp/process.md\n"
             "          meshless-bench speed --data ../shared/data --markdown bench/RESULTS.md\n");
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::fputs(own_name(a.help_text()).c_str(), stdout);
            return 0;
        }
    a.parse(argc, argv, 1);
    const std::string what = a.positional().empty() ? "all" : a.positional()[0];
    if (what != "all" && what != "accuracy" && what != "speed" && what != "threads" && what != "splat" &&
        what != "ooc" && what != "fields" && what != "process" && what != "multiblock" && what != "render" &&
        what != "scattered" && what != "hierarchy" && what != "hierarchy-rmse" && what != "python" && what != "scale")
        throw UsageError("unknown section '" + what +
                         "' (accuracy, speed, threads, splat, ooc, fields, process, multiblock, render, scattered, hierarchy, "
                         "hierarchy-rmse, python, scale, all)");

    BenchOptions o;
    o.quick = a.has("quick");
    o.reps = static_cast<int>(a.get_int_or("reps", o.quick ? 2 : 10));
    o.process_reps = static_cast<int>(a.get_int_or("reps", o.quick ? 1 : 3));
    o.isovalues = static_cast<int>(a.get_int_or("isovalues", o.quick ? 4 : 16));
    if (o.reps < 1 || o.reps > 100000) throw UsageError("--reps: expected 1..100000");
    if (o.isovalues < 1 || o.isovalues > 1000) throw UsageError("--isovalues: expected 1..1000");
    o.data_dir = a.get_or("data", default_data_dir());
    o.bench_dir = a.get_or("bench-dir", default_bench_dir());
    o.python = a.get_or("python", "/usr/bin/python3");
    o.scratch_dir = a.get_or("scratch", "");
    o.keep = a.has("keep");
    o.with_ooc = a.has("with-ooc");
    o.meshless = a.get_or("meshless", default_meshless());
    o.work_dir = a.get_or("work", "");
    o.large = a.has("large");
    o.scattered_sizes = a.get_or("sizes", "");
    o.scattered_fields = a.get_or("fields", "");
    o.scattered_distributions = a.get_or("distributions", "");
    o.scattered_parts = a.get_or("parts", "");
    if (const auto k = a.get("hardy-c-spacing")) {
        o.hardy_c_spacing = std::stod(*k);
        if (!(o.hardy_c_spacing >= 0)) throw UsageError("--hardy-c-spacing: expected a factor >= 0");
    }
    o.scale_sets = a.get_or("sets", "");
    o.scale_ranks = a.get_or("ranks", "");
    try {
        check_scattered_lists(o);
        check_scale_options(o);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    o.scattered_field = a.get_or("field", "");
    o.hardy_c = a.get_or("hardy-c", "");
    o.peer_timeout = a.get_double_or("peer-timeout", 0);
    if (!(o.peer_timeout >= 0) || o.peer_timeout > 86400) throw UsageError("--peer-timeout: expected 0..86400 seconds");
    o.no_peers = a.has("no-peers");
    o.all_peers = a.has("all-peers");
    o.reuse_peers = a.has("reuse-peers");
    if (!o.scratch_dir.empty() && !fs::is_directory(o.scratch_dir))
        throw UsageError("--scratch: '" + o.scratch_dir + "' is not a folder");

    Report r;
    r.title("meshless-bench " + what + (o.quick ? " (--quick)" : ""));
    r.note("Machine: " + machine_description() + ". Date: " + now_string() + ". " +
           fmt("Options: --reps %d --isovalues %d, data folder %s.", o.reps, o.isovalues, o.data_dir.c_str()));
    if (what == "all" || what == "accuracy") run_accuracy(o, r);
    if (what == "all" || what == "speed") run_speed(o, r);
    if (what == "all" || what == "threads") run_threads(o, r);
    if (what == "all" || what == "splat") run_splat(o, r);
    if (what == "all" || what == "fields") run_fields(o, r);
    if (what == "ooc" || (what == "all" && (o.quick || o.with_ooc || ooc_scratch_has_room(o))))
        run_ooc(o, r);
    else if (what == "all")
        r.note("ooc section skipped: less than 16 GiB free in the scratch folder (give --with-ooc, --scratch DIR, "
               "or run `meshless-bench ooc`).");
    if (what == "all" || what == "process") run_process(o, r);
    if (what == "all" || what == "multiblock") run_multiblock(o, r);
    if (what == "all" || what == "render") run_render(o, r);
    if (what == "all" || what == "scattered") run_scattered(o, r);
    if (what == "all" || what == "hierarchy") run_hierarchy(o, r);
    if (what == "hierarchy-rmse") run_hierarchy_rmse(o, r);
    if (what == "all" || what == "python") run_python(o, r);
    if (what == "scale") run_scale(o, r);
    if (auto md = a.get("markdown")) r.write_markdown(*md);
    return 0;
}

}  // namespace meshless::bench

int main(int argc, char** argv) {
    using namespace meshless;
    if (argc >= 2 && std::strcmp(argv[1], bench::kRusageWrapperFlag) == 0) return bench::run_rusage_wrapper(argc, argv);
    std::signal(SIGPIPE, SIG_IGN);
    try {
        return bench::bench_main(argc, argv);
    } catch (const std::exception& e) {  // the CLI's one mapping (cli/errors.hpp)
        const int code = cli::exit_code(e);
        const std::string msg = cli::error_message(e);
        if (code != cli::kExitOk)
            std::fprintf(stderr, "meshless-bench: %s\n", (code == cli::kExitUsage ? bench::own_name(msg) : msg).c_str());
        return code;
    }
}
