// `meshless hierarchy` and `meshless lod` (dissertation sections 6.3-6.5): a cluster binary tree of
// any volume or scattered data set, saved as .mlh (formats/cluster_tree_file.hpp), and its levels
// of detail as scattered point sets.
#include <chrono>
#include <cstdio>

#include "cli/args.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/field_cli.hpp"
#include "cli/point_set_cli.hpp"
#include "cli/progress_meter.hpp"
#include "formats/atomic_file.hpp"
#include "formats/cluster_tree_file.hpp"
#include "kernels/field_params.hpp"
#include "formats/point_set_reader.hpp"
#include "stream/certified_lod.hpp"
#include "stream/cluster_hierarchy.hpp"

namespace meshless::cli {

namespace {

/// The build's parameters from --max-splits ... --pca-scaling (UsageError for a value out of range).
CbtParams hierarchy_params(const Args& a) {
    CbtParams p;
    if (auto v = a.get("max-splits")) {
        const long long n = parse_int(*v, "--max-splits");
        if (n < 0) throw UsageError("--max-splits: expected a count >= 0");
        p.max_splits = static_cast<std::uint64_t>(n);
    }
    p.max_error = parse_finite(a.get_or("max-error", "0"), "--max-error");
    if (p.max_error < 0) throw UsageError("--max-error: expected a number >= 0");
    const long long mc = a.get_int_or("min-cluster", 2);
    if (mc < 2 || mc > 1000000000) throw UsageError("--min-cluster: expected 2..10^9");
    p.min_cluster = static_cast<std::uint32_t>(mc);
    const long long k = a.get_int_or("neighbours", 25);
    if (k < 1 || k > 1000) throw UsageError("--neighbours: expected 1..1000");
    p.neighbours = static_cast<std::uint32_t>(k);
    p.hardy_c_rel = parse_finite(a.get_or("hardy-c", "0.025"), "--hardy-c");  // ranges: checked at parse
    if (auto c = a.get("hardy-c-world")) p.hardy_c_world = parse_finite(*c, "--hardy-c-world");
    const std::string sc = a.get_or("pca-scaling", "normalised");
    if (sc == "raw") p.scaling = PcaScaling::raw;
    else if (sc == "normalised" || sc == "normalized") p.scaling = PcaScaling::normalised;
    else throw UsageError("--pca-scaling: expected normalised or raw, got '" + sc + "'");
    const std::string order = a.get_or("split-order", "weighted");
    if (order == "weighted") p.order = CbtSplitOrder::weighted;
    else if (order == "max-error") p.order = CbtSplitOrder::max_error;
    else throw UsageError("--split-order: expected weighted or max-error, got '" + order + "'");
    p.size_term = parse_finite(a.get_or("size-term", "0.2"), "--size-term");  // range: checked at parse
    const std::string value = a.get_or("cluster-value", "mean");
    if (value == "mean") p.value = CbtValueKind::mean;
    else if (value == "fit") p.value = CbtValueKind::fit;
    else throw UsageError("--cluster-value: expected mean or fit, got '" + value + "'");
    return p;
}

/// --dims/--type/--spacing/--series/--array (raw volumes), the point-set options: what hierarchy and lod --samples read.
void add_sample_options(Args& a) {
    add_point_set_options(a, /*with_endian=*/true);
    a.option("dims", "", "X,Y,Z", "raw volumes: samples along x, y, z (a raw file whose name does not give them)")
        .option("type", "", "T", "raw volumes: uint8 | int16 | uint16 | float32")
        .option("spacing", "", "SX,SY,SZ", "raw volumes: voxel spacing, world units, 0 < s <= 3.4e38", "1,1,1")
        .option("series", "", "UID|N", "DICOM: the series to read from a folder holding several (its UID, or N in their listing)");
    add_array_option(a);
}

/// What hierarchy INPUT... and lod --samples INPUT read (stream/cluster_hierarchy.hpp read_tree_samples).
TreeSamplesInput tree_samples_input(const Args& a, const std::vector<std::string>& paths) {
    TreeSamplesInput in;
    in.paths = paths;
    in.raw_given = a.has("dims") || a.has("type") || a.has("spacing") || a.has("series") || a.has("array");
    in.array_given = a.has("array");
    if (in.raw_given) in.raw = raw_options(a);
    in.points = point_set_options(a);
    in.command = a.command();
    in.warn = [&a](const std::string& subject, const std::string& what) {
        std::fprintf(stderr, "meshless %s: warning: %s: %s\n", a.command().c_str(), terminal_safe(subject).c_str(), terminal_safe(what).c_str());
    };
    return in;
}

/// lod --max-error E --samples INPUT: the certified level of detail (stream/certified_lod.hpp).
int certified_lod_run(const Args& a, const std::string& out) {
    CertifiedLodJob job;
    job.max_error = parse_finite(*a.get("max-error"), "--max-error");
    if (job.max_error < 0) throw UsageError("--max-error: expected a number >= 0");
    job.tree_path = a.positional().front();
    job.out = out;
    if (a.has("hardy-c")) job.hardy_c_rel = parse_finite(*a.get("hardy-c"), "--hardy-c");
    job.samples = tree_samples_input(a, {*a.get("samples")});
    job.threads = threads(a);
    ProgressMeter meter = ProgressMeter::of(a, "trials", 1);
    job.progress = [&meter](double done, double total) {
        meter.set_total(total);
        meter.set_fraction(done / total);
    };
    if (a.has("stats")) job.stats = stderr;
    const CertifiedLod c = run_certified_lod_job(job);
    meter.done();
    return c.reached ? 0 : kExitEmpty;  // (E not reached: the finest is written, and a script sees it)
}

}  // namespace

int cmd_hierarchy(int argc, char** argv) {
    Args a("hierarchy", "INPUT... -o tree.mlh [options]",
           "Builds the cluster binary tree of dissertation chapter 6 (sections 6.1, 6.3) of any scalar data:\n"
           "a volume (each voxel a sample; a .mlb brick store is read brick by brick), scattered points or\n"
           "multiblock grids. One cluster of every sample\n"
           "is refined by splitting, along the plane through its centre normal to the dominant principal axis\n"
           "of its (x, y, z, f) samples, the cluster of largest |C| x (sigma_c^2 + t^2) (weighted: t = the size\n"
           "term x the value range, so large quiet clusters are split too and the point density of a level\n"
           "of detail does not jump) or of largest error sigma_c = max |f_j - f_c| (max-error, as in section\n"
           "6.3); f_c is the mean of the cluster's samples, or (fit) a local multiquadric over the\n"
           "min(|C|, k) samples nearest the centre. The defaults reconstruct best (the levels of detail beat\n"
           "random samples of their size). Splits that leave a side empty are skipped (counted). The tree\n"
           "(.mlh) is the same for any --threads; meshless lod, meshless info and every command reading point\n"
           "sets (--lod-count/--lod-fraction/--lod-level/--lod-error) take it.");
    a.option("output", "o", "FILE", "the tree (.mlh, required)")
        .option("max-splits", "", "N", "stop after N splits, N >= 0 (default: none)")
        .option("max-error", "", "E", "stop when the worst cluster error is <= E, E >= 0", "0")
        .option("min-cluster", "", "N", "clusters with fewer samples are not split (>= 2)", "2")
        .option("split-order", "", "weighted|max-error", "which cluster is split next (see above)", "weighted")
        .option("size-term", "", "T", "weighted order: t relative to the value range, in [0, 100] (0: no size term)", "0.2")
        .validate(in_range("--size-term", 0, true, 100))
        .option("cluster-value", "", "mean|fit", "f_c: the mean of the cluster's samples or a local multiquadric fit", "mean")
        .option("neighbours", "", "K", "fit: f_c from the min(|C|, K) samples nearest the centre, 1..1000", "25")
        .option("hardy-c", "", "C", "fit: Hardy's multiquadric constant relative to the bounding-box diagonal, in [0, 100]", "0.025")
        .validate(in_range("--hardy-c", 0, true, 100))
        .option("hardy-c-world", "", "C", "fit: Hardy's constant in world units, in (0, 1e150] (overrides --hardy-c)")
        .validate(in_range("--hardy-c-world", 0, false, 1e150))
        .option("pca-scaling", "", "normalised|raw",
                "PCA of (x,y,z,f) in units scaled to the bounding-box diagonal and the value range, or in the data's units",
                "normalised")
        .option("certify", "", "F1,F2,...",
                "also certify the levels of detail of these fractions of the samples, each in (0, 1], at most 64: the largest\n"
                "error of their mpu field at every sample, stored in the tree (meshless info lists it); one field per size")
        .validate([](const std::string& v) {
            for (double f : parse_finite_list(v, "--certify", kMaxCertifiedErrors))
                if (!(f > 0 && f <= 1)) throw UsageError("--certify: expected fractions in (0, 1], got '" + v + "'");
        })
        .flag("stats", "print splits, skipped splits, depth, error, time and memory to stderr");
    add_sample_options(a);
    add_thread_option(a);
    add_quiet_option(a);
    a.positionals(1, 1000);
    a.epilog("examples:\n  meshless hierarchy silicium_98x34x34_uint8.raw -o si.mlh --stats\n"
             "  meshless lod si.mlh --level 15 -o si15.ply\n  meshless info si.mlh");
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string out = require_output_extension(a.require("output"), ".mlh", "-o", "a cluster tree", /*to_stdout=*/false);
    if (is_streaming_output(out)) throw UsageError("-o " + out + ": a cluster tree is written to a regular file (.mlh)");
    const CbtParams p = hierarchy_params(a);
    const int nthreads = threads(a);

    const auto t0 = std::chrono::steady_clock::now();
    const PointSet points = read_tree_samples(tree_samples_input(a, a.positional()));
    const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // a --max-error build makes an unknown number of splits: its progress counts the samples that reached their leaf
    const bool settled = cluster_hierarchy_counts_settled(p, points.size());
    ProgressMeter meter = settled ? ProgressMeter::of(a, "samples", static_cast<double>(points.size()))
                                  : ProgressMeter::of(a, "splits", cluster_hierarchy_split_bound(p, points.size()));
    ClusterTree tree = build_cluster_hierarchy(points, p, nthreads, a.positional().front(), [&](const CbtProgressReport& b) {
        meter.set_fraction(cluster_hierarchy_progress(p, points.size(), b));
    });
    meter.done();
    double certify_s = 0;
    if (auto c = a.get("certify")) {
        const auto tc = std::chrono::steady_clock::now();
        const std::vector<double> fractions = parse_finite_list(*c, "--certify", kMaxCertifiedErrors);
        const std::vector<std::uint64_t> counts = certify_counts(tree, fractions);
        if (counts.size() < fractions.size())
            std::fprintf(stderr, "meshless hierarchy: note: --certify: %zu fractions give %zu distinct sizes of at most %llu points (the tree's leaves)\n",
                         fractions.size(), counts.size(), static_cast<unsigned long long>(tree.stats.splits + 1));
        ProgressMeter sizes = ProgressMeter::of(a, "certified sizes", static_cast<double>(counts.size()));
        tree.certified = certify_lod_sizes(tree, points, counts, lod_hardy_c_rel(p.order == CbtSplitOrder::max_error), nthreads,
                                           [&](std::uint64_t, double) { sizes.add(1); });
        sizes.done();
        certify_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tc).count();
    }
    const auto t1 = std::chrono::steady_clock::now();
    write_cluster_tree_file(out, tree);
    const double write_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    for (const std::string& note : cluster_hierarchy_notes(tree, p)) std::fprintf(stderr, "meshless hierarchy: %s\n", note.c_str());
    if (a.has("stats")) std::fprintf(stderr, "%s\n", cluster_hierarchy_report(tree, p, nthreads, read_s, write_s).c_str());
    if (a.has("stats") && !tree.certified.empty())
        std::fprintf(stderr, "hierarchy: certified %zu level-of-detail sizes at every sample in %.3f s\n", tree.certified.size(), certify_s);
    return 0;
}

int cmd_lod(int argc, char** argv) {
    Args a("lod", "tree.mlh (--count N | --fraction F | --level L | --error E | --max-error E --samples INPUT) -o lod.ply|lod.csv|lod.vtp",
           "Extracts a level of detail from a cluster binary tree: the clusters left after the refinement's\n"
           "first N - 1 splits (--count N, or --fraction F of the samples: the size the tree was refined\n"
           "best to), or (dissertation section 6.4) a depth-first traversal taking the clusters at depth L\n"
           "(level-based) or the first clusters of error <= E on every path (error-based); a leaf met\n"
           "before is taken as it is. The points are listed coarse to\n"
           "fine: any first N of them hold one point below each cluster of a coarser cut of the tree, so a\n"
           "prefix is itself a level of detail spread over all the data. The cluster centres and values are\n"
           "a scattered data set (section 6.5): every command reading point sets takes it, or the .mlh itself\n"
           "with --lod-count/--lod-fraction/--lod-level/--lod-error. A count beyond the leaves, a level beyond\n"
           "the depth or an error below the one reached gives the finest level of detail (with a warning).");
    a.option("output", "o", "FILE", "the points: .ply (binary, double), .csv or .vtp (required)")
        .option("count", "", "N", "the N clusters left after the first N - 1 splits, N >= 1")
        .option("fraction", "", "F", "the same for N = F x the samples (rounded, at least 1), 0 < F <= 1")
        .validate(in_range("--fraction", 0, false, 1))
        .option("max-error", "", "E", "certified: a level of detail (by count) whose field is within E >= 0 of every sample of\n"
                "--samples (checked at each), found by bisection over the count: one point fewer misses E, a smaller\n"
                "one may exist where the error does not fall with the count; a size the tree certified (hierarchy\n"
                "--certify) within E bounds the search. Unreachable: a warning, the finest level of detail, exit 4")
        .option("samples", "", "INPUT", "--max-error: the data the tree was built from (as given to hierarchy)")
        .option("hardy-c", "", "C", "--max-error: the mpu field's Hardy c relative to the bounding-box diagonal, in (0, 100]\n"
                "(default: a level of detail's, as its readers use it: 0.003 for a max-error tree, else 0.025)")
        .validate(in_range("--hardy-c", 0, false, 100))
        .option("level", "", "L", "level-based: clusters at depth L >= 0 (0 = the root)")
        .option("error", "", "E", "error-based: clusters whose error is <= E, E >= 0")
        .flag("stats", "print the LOD's size and the extraction time to stderr");
    add_sample_options(a);
    add_thread_option(a);
    add_quiet_option(a);
    a.positionals(1, 1);
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string out = a.require("output");
    require_point_set_output(out, "a level of detail");
    if (int(a.has("level")) + int(a.has("error")) + int(a.has("count")) + int(a.has("fraction")) + int(a.has("max-error")) != 1)
        throw UsageError("give one of --count N, --fraction F, --level L, --error E or --max-error E");
    if (a.has("max-error") != a.has("samples")) throw UsageError("--max-error E needs --samples INPUT (the tree's data), and --samples needs --max-error");
    if (a.has("max-error")) return certified_lod_run(a, out);
    PointSetOptions o;
    if (auto v = a.get("count")) {
        o.lod_count = lod_count_arg(*v, "--count");
    } else if (auto f = a.get("fraction")) {
        o.lod_fraction = parse_finite(*f, "--fraction");
    } else if (auto v = a.get("level")) {
        const long long L = parse_int(*v, "--level");
        if (L < 0 || L > 0xFFFFFFFFll) throw UsageError("--level: expected a depth >= 0");
        o.lod_level = static_cast<std::uint32_t>(L);
    } else {
        o.lod_error = parse_finite(*a.get("error"), "--error");
        if (*o.lod_error < 0) throw UsageError("--error: expected a number >= 0");
    }
    run_lod_job(a.positional().front(), o, out, stderr, a.has("stats") ? stderr : nullptr);
    return 0;
}

}  // namespace meshless::cli
