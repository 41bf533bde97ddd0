#include "cli/field_cli.hpp"

#include <algorithm>
#include <cstdio>

#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/point_set_cli.hpp"
#include "cli/progress_meter.hpp"
#include "formats/cluster_tree_file.hpp"
#include "formats/field_hint.hpp"
#include "formats/file_names.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/point_store.hpp"
#include "stream/available_memory.hpp"
#include "kernels/make_field.hpp"
#include "kernels/point_set_identity.hpp"

namespace meshless::cli {

namespace {

/// Options that shape a fit: meaningless with a fitted field file.
constexpr const char* kFitOptions[] = {"binning", "support", "local-points", "max-points", "alpha", "hardy-c", "hardy-c-world", "hardy-c-spacing", "hardy-c-rough", "normalise-axes"};

BuiltField load_file(const Args& a, const std::string& path) {
    for (const char* opt : kFitOptions)
        if (a.has(opt))
            throw UsageError("--" + std::string(opt) + ": the field comes fitted from " + path +
                             " (its options are in the file, see meshless info); leave --" + opt + " out");
    BuiltField f = load_built_field(path);
    if (a.has("stats")) print_field_load_report(stderr, a.command(), path, *f.file, f.load_seconds);
    return f;
}

}  // namespace

void add_field_options(Args& a, bool with_coverage, const std::string& default_kind) {
    a.option("field", "", "NAME|FILE.mlf",
             "rbf-grid (section 4.3) | mpu (section 5.5) | global-rbf (small sets), or a field fitted by "
             "meshless fit (.mlf; it must have been fitted to these points)",
             default_kind)
        .option("binning", "", "M", "rbf-grid: binning constant m, about points per RBF-grid cell, > 0 (at most 8 cells a point)", "5")
        .option("support", "", "27|paper", "rbf-grid: blend the 27 neighbour cells (continuous) or the paper's radius 2|s|", "27")
        .option("local-points", "", "K",
                "rbf-grid: a local fit keeps its nearest max(K, points within its weight radius) points, 0..100000; 0 = all in its 27 cells",
                std::to_string(FieldParams{}.rbf_grid_local_points))
        .option("max-points", "", "N", "mpu: subdivide while a node's sphere holds more than N points, 8..100000", "140")
        .option("alpha", "", "A", "mpu: sphere of influence = A x node diagonal, in (0.5, 4]; the octree and its fits grow "
                                  "as A^3 and must fit in memory", "0.75")
        .option("hardy-c", "", "C", "Hardy's multiquadric constant relative to the bounding-box diagonal, in (0, 100] "
                                     "(a level of detail of a max-error .mlh tree: 0.003)", "0.025")
        .validate(in_range("--hardy-c", 0, false, 100))
        .option("hardy-c-world", "", "C", "Hardy's constant in world units, in (0, 1e150] (overrides --hardy-c)")
        .validate(in_range("--hardy-c-world", 0, false, 1e150))
        .option("hardy-c-spacing", "", "K",
                "rbf-grid, mpu: a local fit's c is at most K x its point spacing (mean nearest-neighbour distance), "
                "which keeps dense data well conditioned; 0 = the global c everywhere (the paper); 0..1e6",
                "8")
        .validate(in_range("--hardy-c-spacing", 0, true, 1e6))
        .option("hardy-c-rough", "", "K",
                "rbf-grid, mpu: each local is also fitted with c = K x its point spacing and keeps the fit that predicts "
                "its own points better (leave-one-out; the narrow c wins at sharp edges); 0 = one fit; 0..1e6",
                "1")
        .validate(in_range("--hardy-c-rough", 0, true, 1e6))
        .flag("normalise-axes", "scale each axis so the bounding box is a cube (axes in unrelated units)");
    if (with_coverage)
        a.option("max-gap", "", "F", "positions farther than F >= 0 x the local point spacing (8th-neighbour distance) "
                 "from the data, and not surrounded by it, are outside it (see --extrapolate); every value is kept "
                 "within the data's value range; 0: the field's raw values everywhere", "1")
            .option("extrapolate", "", "nan|clamp|nearest",
                    "outside the data: NaN, the field's value kept within the data range (where the field has one), or "
                    "the nearest data value", "nan");
    a.flag("stats", "print what building (or loading) the field did (merged points, fallbacks, sizes, time) to stderr");
    add_point_set_options(a, /*with_endian=*/true);
    add_thread_option(a);
}

std::optional<std::string> field_file_arg(const Args& a) {
    const auto v = a.get("field");
    if (!v) return std::nullopt;
    FieldKind k;
    if (parse_field_kind(*v, k)) return std::nullopt;
    if (ends_with_ci(*v, ".mlf") || is_field_file(*v)) return *v;
    return std::nullopt;
}

std::string field_kind_arg(const Args& a, const std::string& default_kind) {
    if (const auto v = a.get("field")) return *v;
    if (!default_kind.empty()) return default_kind;
    const std::string d = a.default_of("field");
    return d.empty() ? kBlocksFieldDefault : d;
}

namespace {
/// An option that tunes one kind of field, given with another, would be silently ignored: a usage
/// error naming the field it is for (a fitted .mlf: load_file refuses every fit option).
void refuse_other_fields_options(const Args& a, const std::string& kind) {
    static const struct {
        const char* option;
        const char* field;
    } kTuning[] = {{"binning", "rbf-grid"}, {"support", "rbf-grid"}, {"local-points", "rbf-grid"},
                   {"max-points", "mpu"},    {"alpha", "mpu"}};
    for (const auto& t : kTuning)
        if (a.declared(t.option) && a.has(t.option) && kind != t.field)
            throw UsageError("--" + std::string(t.option) + " tunes the " + t.field + " field; the field here is " + kind +
                             " (--field " + t.field + " to use it)");
}
}  // namespace

FieldParams field_params(const Args& a, const std::string& default_kind) {
    FieldParams p;
    const std::string kind = field_kind_arg(a, default_kind);
    if (field_file_arg(a)) throw UsageError("--field " + kind + ": a fitted field file, not a field to build");
    if (!parse_field_kind(kind, p.kind))
        throw UsageError("--field: expected rbf-grid, mpu, global-rbf or a fitted field file (.mlf), got '" + kind + "'");
    refuse_other_fields_options(a, kind);
    p.binning_m = parse_finite(a.get_or("binning", "5"), "--binning");
    if (!(p.binning_m > 0)) throw UsageError("--binning: expected a number > 0, got " + a.get_or("binning", "5"));
    const std::string support = a.get_or("support", "27");
    if (support == "27") p.rbf_grid_support = RbfGridSupport::neighbours27;
    else if (support == "paper") p.rbf_grid_support = RbfGridSupport::paper_radius;
    else throw UsageError("--support: expected 27 or paper, got '" + support + "'");
    const long long n = a.get_int_or("max-points", FieldParams{}.mpu_max_points);
    if (n < 8 || n > 100000) throw UsageError("--max-points: expected 8..100000");
    p.mpu_max_points = static_cast<std::uint32_t>(n);
    p.mpu_min_points = std::min(p.mpu_min_points, p.mpu_max_points);  // grown leaves never exceed N
    p.mpu_alpha = parse_finite(a.get_or("alpha", "0.75"), "--alpha");
    if (!(p.mpu_alpha > 0.5) || p.mpu_alpha > kMaxMpuAlpha)  // 0.5: the sphere no longer covers its cube
        throw UsageError("--alpha: expected a factor in (0.5, 4], got " + a.get_or("alpha", "0.75"));
    if (const auto c = a.get("hardy-c")) {
        p.hardy_c_rel = parse_finite(*c, "--hardy-c");  // its range: checked at parse (in_range)
    } else  // a level of detail gets its own default c (kernels/field_params.hpp): a cluster tree's, or the one its file carries
        for (const std::string& in : a.positional()) {
            if (const auto order = cluster_tree_split_order(in)) p.hardy_c_rel = lod_hardy_c_rel(*order == CbtSplitOrder::max_error);
            else if (const auto c = point_file_field_hint(in)) p.hardy_c_rel = *c;
            else continue;
            break;
        }
    if (auto c = a.get("hardy-c-world")) p.hardy_c_world = parse_finite(*c, "--hardy-c-world");
    for (const auto& [opt, to] : {std::pair<const char*, double*>{"hardy-c-spacing", &p.hardy_c_spacing}, {"hardy-c-rough", &p.hardy_c_rough}})
        if (auto k = a.get(opt)) *to = parse_finite(*k, "--" + std::string(opt));
    p.normalise_axes = a.has("normalise-axes");
    const long long k = a.get_int_or("local-points", FieldParams{}.rbf_grid_local_points);
    if (k < 0 || k > 100000) throw UsageError("--local-points: expected 0..100000");
    p.rbf_grid_local_points = static_cast<std::uint32_t>(k);
    return p;
}

PointSet read_field_points(const std::vector<std::string>& paths, const Args& a, bool warn_dropped) {
    const InputWarning to_stderr = [&a](const std::string& subject, const std::string& what) {
        std::fprintf(stderr, "meshless %s: warning: %s: %s\n", a.command().c_str(), terminal_safe(subject).c_str(), terminal_safe(what).c_str());
    };
    return meshless::read_field_points(paths, point_set_options(a), a.command(), to_stderr, warn_dropped);
}

PointSet read_points_arg(const Args& a, bool warn_dropped) {
    if (a.positional().empty()) throw UsageError("missing POINTS argument (see meshless " + a.command() + " --help)");
    return read_field_points(a.positional(), a, warn_dropped);
}

std::unique_ptr<Field> fit_input_field(const Args& a, const PointSet& points, const FieldParams& params, FieldBuildStats& stats,
                                       const FitShare* share) {
    const int n = threads(a);
    // the commands that show progress (they declare --quiet) show the local fits too
    ProgressMeter meter = ProgressMeter::of(a, "local fits", 1);  // the total comes with the first report
    if (params.kind == FieldKind::mpu)  // before any fit: the octree that --alpha implies
        check_option_fits(a, "--alpha " + a.get_or("alpha", "0.75"),
                          "an mpu octree over " + std::to_string(points.size()) + " points (estimate)",
                          mpu_octree_bytes_estimate(points.size(), params), "give a smaller --alpha");
    FieldProgress progress;
    if (a.declared("quiet"))
        progress = [&meter](double done, double total) {
            meter.set_total(total);
            meter.add(done);
        };
    auto field = fit_data_field(points, params, joined_names(a.positional()), n, &stats, progress, share);
    meter.done();
    return field;
}

BuiltField build_field(const Args& a, const PointSet& points, const std::string& default_kind, const FitShare* share) {
    BuiltField f;
    if (const auto path = field_file_arg(a)) {
        f = load_file(a, *path);
        check_fitted_to(*f.file, point_set_identity(points), *path);
    } else {
        const FieldParams params = field_params(a, default_kind);
        FieldBuildStats st;
        f.field = fit_input_field(a, points, params, st, share);
        // under MPI every rank builds the same field (the fits gathered): rank 0 reports it
        if (a.has("stats") && (!share || share->rank == 0)) print_field_build_report(stderr, a.command(), params, points, st);
    }
    if (a.declared("max-gap")) {
        const SupportTestOptions t = support_test_options(a);
        if (t.max_gap > 0) f.coverage = std::make_unique<PointCoverage>(points.pos, points.value, t.max_gap);
        f.extrapolate = t.extrapolate;
    }
    return f;
}

SupportTestOptions support_test_options(const Args& a) {
    SupportTestOptions t;
    t.max_gap = parse_finite(a.get_or("max-gap", "1"), "--max-gap");
    if (t.max_gap < 0) throw UsageError("--max-gap: expected a factor >= 0");
    const std::string e = a.get_or("extrapolate", "nan");
    if (e == "nan") t.extrapolate = Extrapolate::nan;
    else if (e == "clamp") t.extrapolate = Extrapolate::clamp;
    else if (e == "nearest") t.extrapolate = Extrapolate::nearest;
    else throw UsageError("--extrapolate: expected nan, clamp or nearest, got '" + e + "'");
    if (t.max_gap == 0 && a.has("extrapolate")) throw UsageError("--extrapolate needs a support test: it has no effect with --max-gap 0");
    return t;
}

void add_store_memory_option(Args& a) {
    a.option("memory", "", "BYTES",
             "a point store (.mlc) with the mpu field: the budget its slabs along z are sized to, e.g. 512M, 2G "
             "(default: the memory this process may use); the output does not depend on it. Other inputs are held whole")
        .validate([](const std::string& v) { (void)parse_memory_size(v); });
}

bool queries_store_slabs(const Args& a, bool warn) {
    const bool slabs = a.positional().size() == 1 && !field_file_arg(a) && is_point_store(a.positional()[0]) &&
                       field_kind_arg(a, kPointsFieldDefault) == "mpu";
    if (warn && !slabs && a.has("memory"))  // (a budget the run cannot keep: say so rather than exceed it silently)
        std::fprintf(stderr, "meshless %s: warning: --memory bounds only a point store (.mlc) with the mpu field; these points "
                             "and their field are held in memory whole\n", a.command().c_str());
    return slabs;
}

StoreQueryParams store_query_params(const Args& a) {
    StoreQueryParams p;
    p.field = field_params(a, kPointsFieldDefault);
    const SupportTestOptions t = support_test_options(a);
    p.max_gap = t.max_gap;
    p.extrapolate = t.extrapolate;
    p.memory_bytes = a.has("memory") ? parse_memory_size(*a.get("memory")) : available_memory();
    return p;
}

BuiltField load_field_arg(const Args& a) {
    const auto path = field_file_arg(a);
    if (!path)
        throw UsageError("--field: " + a.command() + " needs a fitted field file (.mlf, made by meshless fit), got '" +
                         a.get_or("field", "") + "'");
    return load_file(a, *path);
}

}  // namespace meshless::cli
