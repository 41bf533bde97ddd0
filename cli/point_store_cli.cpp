#include "cli/point_store_cli.hpp"

#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/point_set_cli.hpp"
#include "cli/progress_meter.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/point_store.hpp"
#include "formats/text_header.hpp"
#include "ooc/point_store_writer.hpp"

namespace meshless::cli {

namespace {

bool ends_with_mlc(const std::string& s) {
    return s.size() >= 4 && to_lower(s.substr(s.size() - 4)) == ".mlc";
}

}  // namespace

bool point_store_output_requested(int argc, char** argv) {
    for (int i = 2; i < argc; ++i) {
        const std::string t = argv[i];
        if (t == "--") break;
        if ((t == "-o" || t == "--output") && i + 1 < argc) {
            if (ends_with_mlc(argv[i + 1])) return true;
        } else if (t.rfind("--output=", 0) == 0) {
            if (ends_with_mlc(t.substr(9))) return true;
        } else if (t.rfind("-o", 0) == 0 && t.size() > 2 && t[2] != '-') {
            if (ends_with_mlc(t.substr(2))) return true;
        }
    }
    return false;
}

int cmd_convert_points(int argc, char** argv) {
    Args a("convert", "POINTS... -o pts.mlc [--memory BYTES] [--brick-points B] [--zstd-level N] [--threads N]",
           "Converts point sets (any file the point-set readers take: CSV/TSV/text, PLY, .vtp, .vts, .vtu,\n"
           "PLOT3D, raw float32 records, .npy, .mlc; several files = one set) into a point store (.mlc): the points\n"
           "in Morton order, cut into zstd-compressed bricks that are octree cells of at most B points, with\n"
           "per-brick bounds, counts, value ranges and CRC-32s in a tail index (section 3.6's Morton order).\n"
           "NaN/Inf points are dropped and counted. Memory stays within --memory for any number of points\n"
           "(an external sort in runs spilled beside the output when they do not fit); PLY and .mlc inputs\n"
           "are streamed, other formats are read one file at a time. Writes to a temporary name and renames:\n"
           "the same input and options give the same bytes, whatever --threads and --memory.");
    a.option("output", "o", "FILE", "point store to write (required; .mlc)")
        .option("memory", "", "BYTES", "memory budget, e.g. 256M, 2G (too small for one brick: an error)", "256M")
        .validate([](const std::string& v) { (void)parse_memory_size(v); })
        .option("brick-points", "", "B", "points per brick at most, 1..1048576", "4096")
        .option("zstd-level", "", "N", "zstd level, 1..19", "1")
        .deprecated_alias("level")
        .flag("stats", "print points, bricks, runs, size and time to stderr");
    a.positionals(1, std::numeric_limits<std::size_t>::max());
    add_thread_option(a);
    add_quiet_option(a);
    add_point_set_options(a, true);
    a.epilog("example: meshless convert ../shared/data/scattered/sparsePoints.txt -o pts.mlc --stats\n");
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().empty()) throw UsageError("expected POINTS arguments (see meshless convert --help)");
    const std::string out = a.require("output");
    if (out == "-") throw UsageError("-o -: a point store must be written to a file, not standard output");
    require_output_extension(out, ".mlc", "-o", "a point store", /*to_stdout=*/false);
    for (const std::string& p : a.positional())
        if (p == "-") throw UsageError("-: a point store is converted from files, not standard input");
    PointStoreParams p;
    const long long b = a.get_int_or("brick-points", 4096);
    if (b < 1 || b > kPointStoreMaxBrickPoints)
        throw UsageError("--brick-points: expected 1.." + std::to_string(kPointStoreMaxBrickPoints) + ", got " + std::to_string(b));
    p.brick_points = static_cast<std::uint32_t>(b);
    const long long l = a.get_int_or("zstd-level", 1);
    if (l < 1 || l > 19) throw UsageError("--zstd-level: expected a zstd level 1..19, got " + std::to_string(l));
    p.zstd_level = static_cast<int>(l);
    p.threads = threads(a);
    p.memory_bytes = parse_memory_size(a.get_or("memory", "256M"));
    ProgressMeter meter = ProgressMeter::of(a, "points", 0);
    const PointStoreStats st = convert_to_point_store(
        a.positional(), point_set_options(a), out, p, [&](const char* phase, std::uint64_t done, std::uint64_t total) {
            if (std::strcmp(phase, "write") == 0 && total > 0) meter.set_fraction(static_cast<double>(done) / static_cast<double>(total));
        });
    meter.done();
    if (a.has("stats")) std::fprintf(stderr, "%s\n", point_store_stats_line(st, out, p.brick_points).c_str());
    return 0;
}

}  // namespace meshless::cli
