#include "stream/scattered_isosurface.hpp"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>

#include "formats/terminal_safe.hpp"
#include "kernels/barycentric_lattice.hpp"
#include "kernels/errors.hpp"
#include "kernels/marching_stencils.hpp"
#include "stream/dedup_sink.hpp"
#include "stream/projection_meta.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/stencil_source.hpp"
#include "stream/stream_metadata.hpp"
#include "stream/text_format.hpp"
#include "stream/seconds_since.hpp"

namespace meshless {

namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

std::int64_t largest_stencil_points(const BinningGrid& g, const BinnedPoints& b) {
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

namespace {

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

}  // namespace

void warn_about_binning(const BinningGrid& grid, std::int64_t most, std::uint64_t points, const std::string& name,
                        const BinningGridParams& bp, const InputWarning& warn) {
    const int degenerate = int(grid.degenerate[0]) + int(grid.degenerate[1]) + int(grid.degenerate[2]);
    if (degenerate > 0) {
        std::string axes;
        for (int ax = 0; ax < 3; ++ax)
            if (grid.degenerate[static_cast<std::size_t>(ax)]) axes += std::string(axes.empty() ? "" : ", ") + axis_name(ax);
        warn(name, format_text("all points lie on a %s (no extent along %s): the binning grid gives %s one cell; the surface is "
                          "the field's where it defines one off the data",
                          degenerate == 1 ? "plane" : "line", axes.c_str(), degenerate == 1 ? "that axis" : "those axes"));
    }
    if (grid.coarsened)
        warn(name, format_text("the binning rule asks for level %d (%lld cells); coarsened to level %d (%lld cells) by --max-cells "
                          "%lld / --max-level %d: stencils hold more points",
                          grid.rule_level,
                          static_cast<long long>(std::pow(std::ldexp(1.0, grid.rule_level) + 2, 3 - degenerate) * std::pow(3.0, degenerate)),
                          grid.level, static_cast<long long>(grid.cell_count()), static_cast<long long>(bp.max_cells), bp.max_level));
    // section 5.8: "pathological point distributions ... causing the tetrahedrization of a possibly large
    // number of points" (e.g. two far-apart clusters: the depth-first rule stops at the root)
    if (most > 20000 && double(most) > 0.25 * double(points))
        warn(name, format_text("one 3x3x3 stencil of the level-%d binning grid holds %lld of the %llu points (a pathological "
                          "distribution for the binning rule, section 5.8): its Delaunay runs on one thread",
                          grid.level, static_cast<long long>(most), static_cast<unsigned long long>(points)));
}

namespace {

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

bool ScatteredIsosurfaceInput::crosses(double iso) const {
    const auto r = points.value_range();
    return iso >= r[0] && iso <= r[1];
}

StencilInput ScatteredIsosurfaceInput::stencils(const Field& field) const {
    return StencilInput{grid, bins, std::span<const Vec3>(points.pos), std::span<const double>(points.value), field, coverage.get()};
}

ScatteredIsosurfaceInput bin_scattered_points(PointSet points, const std::string& source, const std::string& name,
                                              const BinningGridParams& bp, double reg_gap, const InputWarning& warn) {
    ScatteredIsosurfaceInput in;
    in.source = source;
    in.points = std::move(points);
    if (distinct_positions(in.points.pos, 4) < 4)
        throw FormatError(name + ": fewer than 4 distinct point positions; a volume needs at least 4 points not all in one place");
    const auto t0 = Clock::now();
    in.grid = make_binning_grid(in.points.pos, bp);
    in.bins = bin_points(in.grid, in.points.pos);
    in.octree_seconds = seconds_since(t0);
    in.reg_gap = reg_gap;
    if (warn) warn_about_binning(in.grid, largest_stencil_points(in.grid, in.bins), in.points.size(), name, bp, warn);
    return in;
}

double build_alongside_coverage(ScatteredIsosurfaceInput& in, int threads, const std::function<void()>& build) {
    double seconds = 0;
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(std::max(threads, 1)));
    oneapi::tbb::parallel_invoke(
        [&] {
            const auto t0 = Clock::now();
            build();
            seconds = seconds_since(t0);
        },
        [&] {
            if (in.reg_gap <= 0) return;
            const auto t0 = Clock::now();
            in.coverage = std::make_unique<PointCoverage>(in.points.pos, in.reg_gap);
            in.coverage_seconds = seconds_since(t0);
        });
    return seconds;
}

IsosurfaceField fit_scattered_field(ScatteredIsosurfaceInput& in, double iso, int n, const std::string& producer,
                                   const FieldProjectParams* np, int threads, const std::string& kind,
                                   const std::function<BuiltField()>& build) {
    IsosurfaceField f;
    f.meta = scattered_isosurface_meta(in, iso, n, producer);
    if (np) widen_frame_for_travel(f.meta, np->seed_max_travel);
    if (in.crosses(iso)) f.seconds = build_alongside_coverage(in, threads, [&] { f.field = build(); });
    f.name = f.field.field ? f.field.field->name() : kind;
    if (np) add_projection_meta(f.meta, f.name, *np);
    return f;
}

StreamMeta scattered_isosurface_meta(const ScatteredIsosurfaceInput& in, double iso, int n, const std::string& producer) {
    return scattered_isosurface_meta(in.grid, in.points.size(), in.points.value_range(), in.source, iso, n, producer);
}

StreamMeta scattered_isosurface_meta(const BinningGrid& grid, std::uint64_t points, const std::array<double, 2>& range,
                                     const std::string& source, double iso, int n, const std::string& producer) {
    const double max_travel = kDefaultMaxTravel;
    StreamMeta m;
    m.set("source", source);
    m.set("method", "scattered");
    m.set("iso", iso);
    m.set("samples", std::to_string(n));
    m.set("points", std::to_string(points));
    m.set("binning_level", std::to_string(grid.level));
    m.set("value_min", range[0]);
    m.set("value_max", range[1]);
    const std::array<Vec3, 2> frame = frame_box(grid, max_travel);
    m.set("bounds_lo", triple(frame[0]));
    m.set("bounds_hi", triple(frame[1]));
    m.set("frame", "points");  // a box that holds every point, not the surface's: pictures frame the points
    m.set("volume_bounds_lo", triple(grid.bounds[0]));
    m.set("volume_bounds_hi", triple(grid.bounds[1]));
    m.set("frame_travel", max_travel);  // what the frame allows for
    m.set("frame_cell_diagonal", grid.diagonal());
    m.set("producer", producer);
    return m;
}

ScatteredIsosurfaceStats run_scattered_isosurface(const ScatteredIsosurfaceInput& in, const Field* field, double iso, int n,
                                                  const FieldProjectParams& np, double dedup, const Stage* draw, Sink& out,
                                                  const RunOptions& opt, const std::function<void(double)>& progress) {
    ScatteredIsosurfaceStats st;
    std::optional<DedupSink> dedup_sink;
    if (dedup > 0) dedup_sink.emplace(out, dedup, 0.1 * in.grid.diagonal());
    Sink& sink = dedup_sink ? static_cast<Sink&>(*dedup_sink) : out;
    if (!field) {
        EmptySource empty(Payload::points);
        const Stage* stages[] = {draw};
        run_pipeline(empty, std::span<const Stage* const>(stages, draw ? 1 : 0), sink, opt);
    } else {
        StencilSource source{StencilGrid(in.grid.dims)};
        const StencilSeedStage seed(in.stencils(*field), iso, n);
        static_cast<SeedProjection&>(st) = run_seed_projection(source, seed, *field, iso, np, draw, sink, opt, progress);
        st.seeds = seed.stats();
        st.projected = true;
    }
    if (dedup_sink) st.dedup_removed = dedup_sink->removed();
    return st;
}

StencilSeedStats generate_scattered_seeds(const ScatteredIsosurfaceInput& in, const Field* field, double iso, int n, Sink& sink,
                                          const RunOptions& opt) {
    if (!field) {
        EmptySource empty(Payload::seeds);
        run_pipeline(empty, {}, sink, opt);
        return {};
    }
    StencilSource source{StencilGrid(in.grid.dims)};
    const StencilSeedStage seed(in.stencils(*field), iso, n);
    const Stage* stages[] = {&seed};
    run_pipeline(source, stages, sink, opt);
    return seed.stats();
}

StencilRankResult run_scattered_isosurface_rank(const ScatteredIsosurfaceInput& in, const Field* field, double iso, int n,
                                                const FieldProjectParams& np, double dedup, int rank, int ranks,
                                                RankChannel* channel, Sink* out, const RunOptions& opt,
                                                std::function<void(std::exception_ptr)> on_deal_error) {
    if (rank != 0) {
        if (!field) return {};
        const StencilInput sin = in.stencils(*field);
        return run_stencils_rank(sin, iso, n, np, rank, ranks, *channel, nullptr, opt);
    }
    std::optional<DedupSink> dd;
    if (dedup > 0) dd.emplace(*out, dedup, 0.1 * in.grid.diagonal());
    Sink& sink = dd ? static_cast<Sink&>(*dd) : *out;
    if (!field) {
        sink.finish();
        return {};
    }
    const StencilInput sin = in.stencils(*field);
    return run_stencils_rank(sin, iso, n, np, 0, ranks, *channel, &sink, opt, std::move(on_deal_error));
}

StencilRankResult sum_stencil_rank_stats(const StencilRankResult& mine,
                                         const std::function<std::vector<std::int64_t>(const std::vector<std::int64_t>&)>& sum_to_root) {
    const auto v = mine.seeds.as_array();
    const FieldNewtonStats& ns = mine.newton;
    std::vector<std::int64_t> all(v.begin(), v.end());
    for (std::int64_t x : {ns.input, ns.converged, ns.flat, ns.too_far, ns.not_converged, ns.stalled, ns.nonfinite, ns.evaluations})
        all.push_back(x);
    const std::vector<std::int64_t> sums = sum_to_root(all);
    StencilRankResult tot;
    tot.rows_per_rank = mine.rows_per_rank;
    if (sums.size() != all.size()) return tot;
    std::array<std::int64_t, StencilSeedStats::kCounters> sv{};
    std::copy(sums.begin(), sums.begin() + StencilSeedStats::kCounters, sv.begin());
    sv[StencilSeedStats::kMaxIndex] = v[StencilSeedStats::kMaxIndex];  // (rank 0's)
    tot.seeds = StencilSeedStats::from_array(sv);
    const std::size_t k = StencilSeedStats::kCounters;
    FieldNewtonStats& t = tot.newton;
    t.input = sums[k]; t.converged = sums[k + 1]; t.flat = sums[k + 2]; t.too_far = sums[k + 3];
    t.not_converged = sums[k + 4]; t.stalled = sums[k + 5]; t.nonfinite = sums[k + 6]; t.evaluations = sums[k + 7];
    return tot;
}

BinningSummary binning_summary(const ScatteredIsosurfaceInput& in) {
    return BinningSummary{in.grid, in.points.size(), in.points.dropped_nonfinite, in.bins.empty_cells, in.bins.empty_interior_cells,
                          in.bins.max_per_cell};
}

void print_scattered_stats(std::FILE* out, const char* cmd, const BinningSummary& b, const StencilSeedStats& s, int n) {
    const auto& g = b.grid;
    std::fprintf(out,
                 "%s: %llu points (%llu NaN/Inf dropped); binning level %d (rule %d%s), grid %lldx%lldx%lld = %lld cells, "
                 "%lld empty (%lld inside the border layer), at most %u points in a cell\n",
                 cmd, static_cast<unsigned long long>(b.points), static_cast<unsigned long long>(b.dropped), g.level, g.rule_level,
                 g.coarsened ? ", coarsened" : "", static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]),
                 static_cast<long long>(g.dims[2]), static_cast<long long>(g.cell_count()), static_cast<long long>(b.empty),
                 static_cast<long long>(b.empty_interior), b.max_per_cell);
    std::fprintf(out,
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

void print_dedup_stats(std::FILE* out, const char* cmd, double dedup, std::int64_t removed) {
    std::fprintf(out, "%s: --dedup %g removed %lld near-duplicate points\n", cmd, dedup, static_cast<long long>(removed));
}

void warn_if_unconverged(std::FILE* out, const std::string& source, const ScatteredIsosurfaceStats& st,
                         const std::string& field_name) {
    const FieldNewtonStats& ns = st.newton;
    if (st.projected && ns.input > 0 && 2 * ns.converged < ns.input)
        std::fprintf(out,
                     "meshless: warning: %s: %lld of %lld seeds did not converge onto the %s field's isosurface (too far %lld, "
                     "non-finite %lld): the field does not resolve this point distribution there\n",
                     terminal_safe(source).c_str(), static_cast<long long>(ns.dropped()), static_cast<long long>(ns.input),
                     field_name.c_str(), static_cast<long long>(ns.too_far), static_cast<long long>(ns.nonfinite));
}

void print_scattered_isosurface_stats(std::FILE* out, const char* cmd, const ScatteredIsosurfaceInput& in,
                                      const ScatteredIsosurfaceStats& st, int n, const std::string& field_name,
                                      const FieldProjectParams& np, double dedup, std::size_t points,
                                      const IsosurfaceRunTimes& t, int threads) {
    const StencilSeedStats& s = st.seeds;
    print_scattered_stats(out, cmd, binning_summary(in), s, n);
    if (st.projected) print_newton_stats(out, cmd, field_name, np, st.newton, st.newton_busy_seconds);
    if (dedup > 0) print_dedup_stats(out, cmd, dedup, st.dedup_removed);
    std::fprintf(out,
                 "%s: %zu points; time: read %.3f s, octree + binning %.3f s, coverage %.3f s and field %.3f s side by side, regularisation %.3f s busy, "
                 "isosurface (stencils + Delaunay + seeds + Newton + output) %.3f s (busy: stencils %.3f s of which "
                 "Delaunay %.3f s, Newton %.3f s over %d thread(s)), total %.3f s\n",
                 cmd, points, in.read_seconds, in.octree_seconds, in.coverage_seconds, t.field, 1e-9 * double(s.regularisation_ns),
                 t.graph, st.seed_busy_seconds, 1e-9 * double(s.delaunay_ns), st.newton_busy_seconds, threads, t.total);
}

void print_scattered_ranks_stats(std::FILE* out, const char* cmd, const ScatteredIsosurfaceInput& in, const StencilRankResult& tot,
                                 int n, const std::string& field_name, const FieldProjectParams& np, std::size_t points, int ranks,
                                 const IsosurfaceRunTimes& t, int threads) {
    print_scattered_stats(out, cmd, binning_summary(in), tot.seeds, n);
    print_newton_stats(out, cmd, field_name, np, tot.newton, 0.0);
    std::string dealt;
    for (std::size_t r = 0; r < tot.rows_per_rank.size(); ++r)
        dealt += (r ? " / " : "") + std::to_string(tot.rows_per_rank[r]);
    std::fprintf(out, "%s: %zu points over %d ranks x %d thread(s); stencil rows dealt on request: %s; time: read %.3f s, "
                 "octree + binning %.3f s, coverage %.3f s and field %.3f s side by side, total %.3f s (rank 0)\n",
                 cmd, points, ranks, threads, dealt.empty() ? "none" : dealt.c_str(), in.read_seconds, in.octree_seconds,
                 in.coverage_seconds, t.field, t.total);
}

void print_scattered_generate_stats(std::FILE* out, const char* cmd, const ScatteredIsosurfaceInput& in, const StencilSeedStats& seeds,
                                    int n, const IsosurfaceRunTimes& t) {
    print_scattered_stats(out, cmd, binning_summary(in), seeds, n);
    std::fprintf(out, "%s: read %.3f s, octree + binning %.3f s, coverage %.3f s and field %.3f s side by side, total %.3f s\n",
                 cmd, in.read_seconds, in.octree_seconds, in.coverage_seconds, t.field, t.total);
}
}  // namespace meshless
