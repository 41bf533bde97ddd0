#include "cli/field_cli.hpp"

#include <oneapi/tbb/global_control.h>

#include <cstdio>

#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/point_set_cli.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/make_field.hpp"

namespace meshless::cli {

void add_field_options(Args& a) {
    a.option("field", "", "NAME", "rbf-grid (section 4.3) | mpu (section 5.5) | global-rbf (small sets)", "rbf-grid")
        .option("binning", "", "M", "rbf-grid: binning constant m, about points per RBF-grid cell", "5")
        .option("support", "", "27|paper", "rbf-grid: blend the 27 neighbour cells (continuous) or the paper's radius 2|s|", "27")
        .option("max-points", "", "N", "mpu: subdivide while a node's sphere holds more than N points", "100")
        .option("alpha", "", "A", "mpu: sphere of influence = A x node diagonal", "0.75")
        .option("hardy-c", "", "C", "Hardy's multiquadric constant relative to the bounding-box diagonal", "0.025")
        .option("hardy-c-world", "", "C", "Hardy's constant in world units (overrides --hardy-c)")
        .flag("normalise-axes", "scale each axis so the bounding box is a cube (axes in unrelated units)")
        .option("max-gap", "", "F", "positions farther than F x the local point spacing (8th-neighbour distance) "
                "from the data are NaN, not extrapolated; 0 keeps every value", "1")
        .flag("stats", "print what building the field did (merged points, fallbacks, sizes, time) to stderr");
    add_point_set_options(a, /*with_endian=*/true);
    add_thread_option(a);
}

FieldParams field_params(const Args& a) {
    FieldParams p;
    const std::string kind = a.get_or("field", "rbf-grid");
    if (!parse_field_kind(kind, p.kind)) throw UsageError("--field: expected rbf-grid, mpu or global-rbf, got '" + kind + "'");
    p.binning_m = parse_finite(a.get_or("binning", "5"), "--binning");
    const std::string support = a.get_or("support", "27");
    if (support == "27") p.rbf_grid_support = RbfGridSupport::neighbours27;
    else if (support == "paper") p.rbf_grid_support = RbfGridSupport::paper_radius;
    else throw UsageError("--support: expected 27 or paper, got '" + support + "'");
    const long long n = a.get_int_or("max-points", 100);
    if (n < 8 || n > 100000) throw UsageError("--max-points: expected 8..100000");
    p.mpu_max_points = static_cast<std::uint32_t>(n);
    p.mpu_alpha = parse_finite(a.get_or("alpha", "0.75"), "--alpha");
    p.hardy_c_rel = parse_finite(a.get_or("hardy-c", "0.025"), "--hardy-c");
    if (auto c = a.get("hardy-c-world")) p.hardy_c_world = parse_finite(*c, "--hardy-c-world");
    p.normalise_axes = a.has("normalise-axes");
    return p;
}

PointSet read_points_arg(const Args& a) {
    if (a.positional().empty()) throw UsageError("missing POINTS argument (see meshless " + a.command() + " --help)");
    return read_point_set(a.positional(), point_set_options(a));
}

BuiltField build_field(const Args& a, const PointSet& points) {
    const FieldParams params = field_params(a);
    const int n = threads(a);
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(n));
    FieldBuildStats st;
    BuiltField f;
    f.field = make_field(points, params, &st);
    const double gap = parse_finite(a.get_or("max-gap", "1"), "--max-gap");
    if (gap < 0) throw UsageError("--max-gap: expected a factor >= 0");
    if (gap > 0) f.coverage = std::make_unique<PointCoverage>(points.pos, gap);
    if (a.has("stats"))
        std::fprintf(stderr,
                     "%s: %s field from %llu points (%llu dropped by the reader as NaN/Inf, %llu blanked; %llu merged as "
                     "near-duplicates), c = %g, %llu local interpolants "
                     "(%llu exact, %llu rank-deficient, %llu regularised, %llu linear fallback), %.1f MiB, %.3f s\n",
                     a.command().c_str(), std::string(field_kind_name(params.kind)).c_str(),
                     static_cast<unsigned long long>(st.input_points),
                     static_cast<unsigned long long>(points.dropped_nonfinite),
                     static_cast<unsigned long long>(points.dropped_blanked), static_cast<unsigned long long>(st.merged_points),
                     st.hardy_c_world, static_cast<unsigned long long>(st.locals),
                     static_cast<unsigned long long>(st.interpolated), static_cast<unsigned long long>(st.rank_deficient),
                     static_cast<unsigned long long>(st.regularised), static_cast<unsigned long long>(st.linear_fallback),
                     st.memory_bytes / 1048576.0, st.build_seconds);
    return f;
}

}  // namespace meshless::cli
