// Brick stores from the command line (docs/architecture.md "Brick store"; dissertation section 3.6):
//   meshless convert VOLUME -o vol.mlb [--brick B] [--zstd-level N] [--threads N]
//   meshless verify vol.mlb...
// (convert ... -o pts.mlc and verify pts.mlc: point stores, cli/point_store_cli.hpp)
//   meshless synth --upsample F [--method trilinear|tricubic] VOLUME -o big.mlb
#include <algorithm>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/progress_meter.hpp"
#include "cli/errors.hpp"
#include "cli/point_store_cli.hpp"
#include "stream/brick_conversion.hpp"
#include "stream/store_verification.hpp"

namespace meshless::cli {

namespace {

// Defaults chosen by measurement (2-core shared VM, 1 thread, best of 3; convert = slab read,
// compression, spool, Morton-order copy and fsync; decode = read + CRC + decompress every brick):
//   dataset (type)          level/brick  ratio  convert MB/s  decode MB/s
//   LIDC2 256x256x133 u8    L1 B16        4.71     132           916
//                           L1 B32        5.55     172          2122
//                           L1 B64        5.72     279          2464
//                           L3 B16/32/64  4.68/5.52/5.66   124/147/139   549/1055/1113
//   tooth 103x94x161 u8     L1 B16/32/64  1.42/1.50/1.50    51/71/82     608/1116/1265
//                           L3 B16/32/64  1.39/1.49/1.53    33/37/37     484/858/881
//   headsq 64x64x93 i16     L1 B16/32/64  1.51/1.58/1.66    38/84/64     640/1013/1127
//                           L3 B16/32/64  1.51/1.67/1.79    34/48/34     606/899/943
//   LIDC2 x2 511x511x265 u8 L1 B16/32/64  5.06/5.99/6.19   155/224/280  1059/1347/1589
//                           L3 B16/32/64  5.10/6.13/6.52   127/205/178   658/1666/1337
// Level 1: on the noisy 8-bit CTs it matches or beats level 3's ratio (LIDC2 5.55 vs 5.52, tooth
// 1.50 vs 1.49 at B32) while converting 1.2-2x and decoding up to 2x faster; level 3 buys 2-6% on
// int16 / smooth data only. Brick 32: 5-18% smaller and 1.3-2.3x faster to decode than 16 (whose
// ghost layer makes each brick 20% bigger than its cells, vs 10% at 32), within 0-5% of 64 while a
// brick (33^3 = 36 KB for u8) is 7.6x smaller, so --memory budgets and the set of bricks an
// isovalue touches stay fine-grained.
constexpr const char* kDefaultBrick = "32";
constexpr const char* kDefaultLevel = "1";

void add_store_options(Args& a) {
    a.option("output", "o", "FILE", "brick store to write (required)")
        .option("brick", "", "B", "cells per brick edge, 2..1024", kDefaultBrick)
        .option("zstd-level", "", "N", "zstd level, 1..19 (1: fastest; on noisy 8-bit CT as small as 3)", kDefaultLevel)
        .deprecated_alias("level")
        .flag("stats", "print bricks, throughput (MB/s) and compression ratio to stderr");
    add_thread_option(a);
    add_quiet_option(a);
}

ConvertParams convert_params(const Args& a) {
    ConvertParams p;
    const long long b = a.get_int_or("brick", std::stoll(kDefaultBrick));
    if (b < 2 || b > 1024) throw UsageError("--brick: expected 2..1024 cells, got " + std::to_string(b));
    p.brick_edge = static_cast<std::uint32_t>(b);
    const long long l = a.get_int_or("zstd-level", std::stoll(kDefaultLevel));
    if (l < 1 || l > 19) throw UsageError("--zstd-level: expected a zstd level 1..19, got " + std::to_string(l));
    p.zstd_level = static_cast<int>(l);
    p.threads = threads(a);
    return p;
}

std::string output_path(const Args& a) {
    const std::string out = a.require("output");
    if (out == "-") throw UsageError("-o -: a brick store must be written to a file, not standard output");
    require_output_extension(out, ".mlb", "-o", "a brick store", /*to_stdout=*/false);
    return out;
}

/// Converts `in` to the store `out` with a progress line over its slices; --stats prints the report.
void run_conversion(ConversionInput in, const std::string& out, ConvertParams p, const Args& a) {
    p.patient_axes = in.labels.patient_axes;
    p.length_unit = in.labels.length_unit;
    p.value_unit = in.labels.value_unit;
    SliceSource& src = *in.slices;
    ProgressMeter meter("meshless " + a.command(), "slices", static_cast<double>(src.grid().dims[2]), progress_wanted(a), progress_delay());
    const ConvertStats st = convert_to_brick_store(src, out, p, [&](double f) { meter.set_fraction(f); });
    meter.done();
    if (a.has("stats")) std::fprintf(stderr, "%s\n", brick_conversion_report(a.command(), src, out, p, st).c_str());
}

}  // namespace

int cmd_convert(int argc, char** argv) {
    if (point_store_output_requested(argc, argv)) return cmd_convert_points(argc, argv);
    Args a("convert", "VOLUME -o vol.mlb [--brick B] [--zstd-level N] [--threads N]",
           "Converts a volume into a brick store (.mlb): cubic bricks of B cells plus a one-voxel ghost\n"
           "layer, each an independent zstd frame in the native sample type with a CRC-32 and value\n"
           "range, in Morton order with a tail index (section 3.6). Streams over z-slabs (memory: one slab\n"
           "of bricks) from raw, NRRD and MetaImage files; other formats are read whole. Writes to a\n"
           "temporary name and renames: the same input and options give byte-identical stores.\n"
           "With -o pts.mlc it converts point sets into a point store instead (meshless convert POINTS... -o\n"
           "pts.mlc --help lists its options).");
    add_store_options(a);
    add_volume_options(a);
    add_crop_option(a);
    a.epilog("example: meshless convert ../shared/data/tooth/tooth_103x94x161_uint8.raw -o tooth.mlb --stats\n");
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().size() != 1) throw UsageError("expected one VOLUME argument (see meshless convert --help)");
    const ConvertParams p = convert_params(a);
    const std::string out = output_path(a);
    run_conversion(open_conversion_input(a.positional()[0], volume_open_options(a, /*stream=*/true)), out, p, a);
    return 0;
}

int cmd_verify(int argc, char** argv) {
    Args a("verify", "STORE.mlb|STORE.mls|STORE.mlc...",
           "Checks stores completely. A brick store (.mlb): header, index and footer checksums, then every\n"
           "brick's CRC-32, decompressed size and value range; prints \"ok: N bricks\", or names the first\n"
           "bad brick by index and voxel range. A sample store (.mls, paradigm A): its header, table and\n"
           "footer, that its brick store is there and unchanged, then every span-space bucket's CRC-32\n"
           "and keys; prints \"ok: N buckets, K cell rows\", or names the first bad bucket. A point store (.mlc):\n"
           "header, index and footer, then every brick's CRC-32, size, points (Morton keys inside its cell,\n"
           "bounds and value range as the index says); prints \"ok: N points in M bricks\". With several\n"
           "stores each line starts with its file name, and every store is checked: exit status 2 when any\n"
           "is damaged. A brick store whose bricks take more than --memory decompressed is not read\n"
           "(exit 1: raise --memory).");
    add_quiet_option(a);
    a.option("memory", "", "BYTES", "the most one decompressed brick may take, e.g. 256M, 2G (a store with bigger bricks is not read)",
             "256M")
        .validate([](const std::string& v) { (void)parse_memory_size(v); });
    a.positionals(1, std::numeric_limits<std::size_t>::max());
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().empty()) throw UsageError("missing store argument (see meshless verify --help)");
    int rc = 0;
    const bool several = a.positional().size() > 1;
    const std::uint64_t memory = parse_memory_size(a.get_or("memory", "256M"));
    for (const std::string& path : a.positional()) {
        const StoreKind kind = verified_store_kind(path);
        std::optional<ProgressMeter> meter;  // a sample store reports no progress
        if (kind != StoreKind::sample) meter.emplace("meshless verify", "bricks", 1, progress_wanted(a), progress_delay());
        const StoreVerdict v = verify_store(path, kind, memory, [&](std::uint64_t done, std::uint64_t total) {
            if (done == 1) meter->set_total(static_cast<double>(total));
            meter->add(1);
        });
        if (meter) meter->done();
        print_store_verdict(stdout, stderr, path, v, several);
        rc = std::max(rc, v.status);
    }
    std::fflush(stdout);
    return rc;
}

int cmd_synth(int argc, char** argv) {
    Args a("synth", "--upsample F [--method trilinear|tricubic] VOLUME -o big.mlb",
           "Makes a bigger test volume from a real one: upsamples VOLUME by the integer factor F\n"
           "(dims (n-1)*F+1, spacing/F) with trilinear or tricubic (Catmull-Rom) interpolation, slice by\n"
           "slice, straight into a brick store; the upsampled volume is never held in memory.");
    a.option("upsample", "", "F", "integer upsampling factor, 1..64 (required)")
        .option("method", "", "M", "trilinear | tricubic", "trilinear");
    add_store_options(a);
    add_volume_options(a);
    a.epilog("example: meshless synth --upsample 2 ../shared/data/vtkjs_LIDC2/LIDC2.vti -o lung.mlb  (511x511x265)\n");
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().size() != 1) throw UsageError("expected one VOLUME argument (see meshless synth --help)");
    const long long f = parse_int(a.require("upsample"), "--upsample");
    if (f < 1 || f > 64) throw UsageError("--upsample: expected an integer factor 1..64, got " + std::to_string(f));
    const std::string m = a.get_or("method", "trilinear");
    Upsampling mode;
    if (m == "trilinear") mode = Upsampling::trilinear;
    else if (m == "tricubic") mode = Upsampling::tricubic;
    else throw UsageError("--method: expected trilinear or tricubic, got '" + m + "'");
    const ConvertParams p = convert_params(a);
    const std::string out = output_path(a);
    run_conversion(open_upsampled_input(a.positional()[0], volume_open_options(a, false), static_cast<int>(f), mode), out, p, a);
    return 0;
}

}  // namespace meshless::cli
