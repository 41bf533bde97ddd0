// meshless bench: the benchmarks of dissertation §3.6 (accuracy, extraction speed and memory vs
// marching cubes and VTK Flying Edges, thread scaling, splat frame rates) and of issue 3 (out of
// core: brick stores, paradigms A and C, peak memory) and of issue 4 (meshless fields). Thin: parses options and
// runs the sections in cli/bench_*.cpp.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "cli/args.hpp"
#include "cli/bench_common.hpp"
#include "cli/commands.hpp"
#include "kernels/errors.hpp"

namespace meshless::cli {

namespace {

namespace fs = std::filesystem;

/// Folder holding flying_edges.py: the source tree this file was compiled from (__FILE__ is
/// absolute in CMake builds), else ../../bench relative to the executable (build/cli/meshless).
std::string default_bench_dir() {
    std::error_code ec;
    const fs::path here(__FILE__);
    if (here.is_absolute()) {
        const fs::path d = here.parent_path().parent_path() / "bench";
        if (fs::exists(d / "flying_edges.py", ec)) return d.string();
    }
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path d = exe.parent_path().parent_path().parent_path() / "bench";
        if (fs::exists(d / "flying_edges.py", ec)) return d.string();
    }
    return "bench";
}

std::string default_data_dir() {
    if (const char* e = std::getenv("MESHLESS_DATA"); e && *e) return e;
    return "../shared/data";
}

}  // namespace

int cmd_bench(int argc, char** argv) {
    Args a("bench", "[accuracy|speed|threads|splat|ooc|fields|all] [options]",
           "Benchmarks of dissertation section 3.6, printed as tables on stdout (progress on stderr):\n"
           "  accuracy  distance / normal / value errors of the projected points on analytic fields, coverage\n"
           "  speed     extraction time and memory: iso-splatting vs marching cubes vs VTK Flying Edges\n"
           "  threads   iso-splatting on 1 and 2 threads, identical output\n"
           "  splat     quad and EWA splat frame times, 36-frame turntable\n"
           "  ooc       brick stores: conversion MB/s and ratio, store vs in-memory throughput, paradigm A vs C\n"
           "            vs marching cubes, threads and MPI ranks, peak RSS on a 4.4 GB volume (minutes, GBs)\n"
           "  fields    meshless fields (rbf-grid, mpu, global-rbf): accuracy vs SciPy RBFInterpolator, linear\n"
           "            reproduction, Table 4.1 construction times, evaluation rate, 1M-point memory (minutes)\n"
           "  all       everything (the default; ooc only with --with-ooc or 16 GiB free in the scratch folder)");
    a.option("data", "", "DIR", "shared test data folder ($MESHLESS_DATA, else ../shared/data)")
        .option("reps", "", "N", "repetitions per isosurface", "10")
        .option("isovalues", "", "K", "isosurfaces per volume", "16")
        .option("markdown", "", "FILE", "also write the tables as markdown (e.g. bench/RESULTS.md)")
        .option("bench-dir", "", "DIR", "folder holding flying_edges.py and rbf_reference.py (default: the source tree's bench/)")
        .option("python", "", "EXE", "Python interpreter with the vtk module (speed) and scipy (fields)", "/usr/bin/python3")
        .option("scratch", "", "DIR", "ooc: folder for its temporary stores (default: the system temp folder)")
        .flag("keep", "ooc: keep the scratch files (stores, the 4.4 GB volume's store)")
        .flag("with-ooc", "all: include the ooc section whatever the free space")
        .flag("quick", "smoke test: 2 reps, 4 isovalues, no large volumes (ooc: LIDC2 x1, no 4 GiB volume, no MPI; "
                       "fields: N = 1K, 10K, no 1M)");
    a.epilog("example: meshless bench speed --data ../shared/data --markdown bench/RESULTS.md\n");
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().size() > 1) throw UsageError("bench: expected at most one section name");
    const std::string what = a.positional().empty() ? "all" : a.positional()[0];
    if (what != "all" && what != "accuracy" && what != "speed" && what != "threads" && what != "splat" &&
        what != "ooc" && what != "fields")
        throw UsageError("bench: unknown section '" + what + "' (accuracy, speed, threads, splat, ooc, fields, all)");

    bench::BenchOptions o;
    o.quick = a.has("quick");
    o.reps = static_cast<int>(a.get_int_or("reps", o.quick ? 2 : 10));
    o.isovalues = static_cast<int>(a.get_int_or("isovalues", o.quick ? 4 : 16));
    if (o.reps < 1 || o.reps > 100000) throw UsageError("--reps: expected 1..100000");
    if (o.isovalues < 1 || o.isovalues > 1000) throw UsageError("--isovalues: expected 1..1000");
    o.data_dir = a.get_or("data", default_data_dir());
    o.bench_dir = a.get_or("bench-dir", default_bench_dir());
    o.python = a.get_or("python", "/usr/bin/python3");
    o.scratch_dir = a.get_or("scratch", "");
    o.keep = a.has("keep");
    o.with_ooc = a.has("with-ooc");
    if (!o.scratch_dir.empty() && !fs::is_directory(o.scratch_dir))
        throw UsageError("--scratch: '" + o.scratch_dir + "' is not a folder");

    bench::Report r;
    r.title("meshless bench " + what + (o.quick ? " (--quick)" : ""));
    r.note("Machine: " + bench::machine_description() + ". Date: " + bench::now_string() + ". " +
           bench::fmt("Options: --reps %d --isovalues %d, data folder %s.", o.reps, o.isovalues, o.data_dir.c_str()));
    if (what == "all" || what == "accuracy") bench::run_accuracy(o, r);
    if (what == "all" || what == "speed") bench::run_speed(o, r);
    if (what == "all" || what == "threads") bench::run_threads(o, r);
    if (what == "all" || what == "splat") bench::run_splat(o, r);
    if (what == "all" || what == "fields") bench::run_fields(o, r);
    if (what == "ooc" || (what == "all" && (o.quick || o.with_ooc || bench::ooc_scratch_has_room(o))))
        bench::run_ooc(o, r);
    else if (what == "all")
        r.note("ooc section skipped: less than 16 GiB free in the scratch folder (give --with-ooc, --scratch DIR, "
               "or run `meshless bench ooc`).");
    if (auto md = a.get("markdown")) r.write_markdown(*md);
    return 0;
}

}  // namespace meshless::cli
