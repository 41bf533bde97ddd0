#include "stream/store_field_queries.hpp"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>

#include "kernels/errors.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/mpu_fit_cache.hpp"
#include "stream/available_cpus.hpp"
#include "stream/field_evaluate_stage.hpp"
#include "stream/field_sinks.hpp"
#include "stream/runner.hpp"
#include "stream/seconds_since.hpp"
#include "stream/store_slab.hpp"

namespace meshless {

namespace {

using QueryClock = std::chrono::steady_clock;
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

/// The queries in z order, as layers [0, count): z(k) does not fall with k; a slab of layers
/// [k0, k1) evaluates source(k0, k1) (positions(k0, k1) of them, whose results take bytes(k0, k1))
/// and hands the exact slab's batches to accept(buffer, k0, k1).
struct QueryLayers {
    std::int64_t count = 0;
    std::function<double(std::int64_t)> z;
    std::function<double(std::int64_t, std::int64_t)> positions;
    std::function<double(std::int64_t, std::int64_t)> bytes;
    std::function<std::unique_ptr<Source>(std::int64_t, std::int64_t)> source;
    std::function<void(BatchBuffer&, std::int64_t, std::int64_t)> accept;
};

std::string budget_mib(double bytes) { return std::to_string(static_cast<std::uint64_t>(std::ceil(bytes / 1048576.0))) + " MiB"; }

void add_slab_field_stats(FieldBuildStats& to, const FieldBuildStats& s) {
    to.locals += s.locals;
    to.interpolated += s.interpolated;
    to.regularised += s.regularised;
    to.linear_fallback += s.linear_fallback;
    to.polynomial_only += s.polynomial_only;
    to.memory_bytes = std::max(to.memory_bytes, s.memory_bytes);
}

/// Runs the layers slab by slab (stream/store_field_queries.hpp): the field and support test of
/// each slab over the points within its halo, checked exact, its batches accepted in order.
FieldQueryStats run_query_slabs(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                const std::array<Vec3, 2>& query_xy, const QueryLayers& q, const FieldQueryRun& run,
                                StoreQueryReport& rep) {
    if (p.field.kind != FieldKind::mpu) throw InvalidArgument("a point store is queried slab by slab with the mpu field only");
    const int threads = run.threads > 0 ? run.threads : available_cpus();
    const StoreBrickIndex index(store);
    const double budget = static_cast<double>(p.memory_bytes);
    MpuFitCache cache;
    // A slab's field holds the fits of the leaves meeting its query box, not of its halo: its bytes
    // go with the points of the query range (the most a point there took so far), the rest of the
    // loaded points cost other_bytes_per_point each; bytes_per_point a loaded point until a field is built.
    double field_per_query_point = 0;
    const std::vector<char> no_bricks(store.bricks().size(), 0);
    const auto query_points = [&](std::int64_t k0, std::int64_t k1) {
        return static_cast<double>(store_slab(store, plan, {q.z(k0), q.z(k1 - 1)}, 0, no_bricks).points);
    };
    const auto need = [&](const StoreSlab& s, std::int64_t k0, std::int64_t k1) {
        const double loaded = static_cast<double>(s.points);
        const double points = field_per_query_point > 0
                                  ? loaded * p.other_bytes_per_point + 1.1 * field_per_query_point * query_points(k0, k1)
                                  : loaded * p.bytes_per_point;
        return points + q.bytes(k0, k1) + 2.0 * static_cast<double>(cache.bytes());
    };
    const double halo0 = store_first_halo(plan, p.field);
    std::vector<std::pair<Vec3, double>> seen;
    FieldQueryStats st;
    for (std::int64_t k0 = 0; k0 < q.count;) {
        double halo = halo0;
        std::vector<char> extra = bricks_still_lacking(store, index, seen, q.z(k0) - halo0);
        const auto slab_of = [&](std::int64_t k1) { return store_slab(store, plan, {q.z(k0), q.z(k1 - 1)}, halo, extra); };
        // the most layers the estimate lets in: doubling, then bisection
        std::int64_t k1 = k0 + 1, step = 1;
        while (k1 < q.count && need(slab_of(std::min(q.count, k1 + step)), k0, std::min(q.count, k1 + step)) <= budget) {
            k1 = std::min(q.count, k1 + step);
            step *= 2;
        }
        for (step /= 2; step > 0; step /= 2)
            if (k1 + step <= q.count && need(slab_of(k1 + step), k0, k1 + step) <= budget) k1 += step;
        for (;;) {
            const StoreSlab slab = slab_of(k1);
            PointSet points = load_store_slab(store, slab, rep.read_seconds);
            rep.loaded += points.size();
            rep.most_loaded = std::max<std::uint64_t>(rep.most_loaded, points.size());
            StoreSlabRegion slab_region(store, plan, index, slab, query_xy);
            FieldRegion& region = slab_region.region;
            const double others = static_cast<double>(points.size()) * p.other_bytes_per_point + q.bytes(k0, k1) +
                                  2.0 * static_cast<double>(cache.bytes());
            region.max_field_bytes = static_cast<std::uint64_t>(std::max(1.0, budget - others));
            FieldBuildStats fst;
            std::unique_ptr<MpuField> field;
            std::unique_ptr<PointCoverage> coverage;
            const auto t0 = QueryClock::now();
            {
                oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
                oneapi::tbb::parallel_invoke(
                    [&] {
                        cache.begin(k1 < q.count ? q.z(k1) : kUnbounded);
                        field = std::make_unique<MpuField>(points, p.field, &fst, FieldProgress{}, nullptr, &region, &cache);
                    },
                    [&] {
                        if (p.max_gap > 0) coverage = std::make_unique<PointCoverage>(points.pos, points.value, p.max_gap);
                    });
            }
            rep.field_seconds += seconds_since(t0);
            field_per_query_point =
                std::max(field_per_query_point, static_cast<double>(fst.memory_bytes) / std::max(1.0, query_points(k0, k1)));
            if (!field->region_exact()) {  // load the bricks the lacking balls meet, and build again
                if (add_lacking_bricks(*field, index, extra, seen) == 0) halo *= 2;
                ++rep.retries;
                continue;
            }
            if (field->over_budget()) {  // fewer layers, as many as the field's size allows; or no kept fits
                ++rep.retries;
                const double room = static_cast<double>(region.max_field_bytes) / static_cast<double>(fst.memory_bytes);
                if (k1 > k0 + 1) {
                    k1 = std::min(k1 - 1, k0 + std::max<std::int64_t>(1, static_cast<std::int64_t>(static_cast<double>(k1 - k0) * room * 0.95)));
                    continue;
                }
                if (cache.bytes() > 0) {
                    cache.clear();
                    continue;
                }
                throw InvalidArgument("--memory " + budget_mib(budget) + " is too small for this store: the field of one slab (" +
                                      std::to_string(points.size()) + " points with its halo) takes " +
                                      budget_mib(static_cast<double>(fst.memory_bytes)) + "; it needs about --memory " +
                                      budget_mib(1.1 * (static_cast<double>(fst.memory_bytes) + others)));
            }
            if (coverage) {
                coverage->set_value_range(plan.value_range);
                coverage->set_part_of(region.loaded);
            }
            const auto t1 = QueryClock::now();
            BatchBuffer buf(Payload::queries);
            const FieldEvaluateStage evaluate(*field, coverage.get(), p.extrapolate);
            const std::unique_ptr<Source> source = q.source(k0, k1);
            const Stage* stages[] = {&evaluate};
            run_pipeline(*source, stages, buf, {threads});
            rep.query_seconds += seconds_since(t1);
            if (coverage && !coverage->part_exact()) {  // the support test read past the loaded z range
                halo *= 2;
                ++rep.retries;
                continue;
            }
            cache.advance();
            st.uncovered += evaluate.uncovered();
            st.clamped += evaluate.clamped();
            st.positions += static_cast<std::size_t>(q.positions(k0, k1));
            q.accept(buf, k0, k1);
            add_slab_field_stats(rep.field, fst);
            rep.halo = std::max(rep.halo, halo);
            ++rep.slabs;
            if (run.progress) run.progress(q.positions(k0, k1));
            break;
        }
        k0 = k1;
    }
    rep.reused_fits = cache.hits();
    return st;
}

}  // namespace

StoreQueries open_store_queries(const std::string& path) {
    StoreQueries q;
    q.store = PointStore::open(path);
    q.plan = plan_scattered_store(*q.store, path, BinningGridParams{}, InputWarning{});
    return q;
}

FieldQueryStats resample_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                     const GridSpec& g, const std::string& path, const FieldQueryRun& run, StoreQueryReport* report) {
    StoreQueryReport rep;
    NrrdVolumeSink sink(g, path, resample_comment("mpu", plan.frame.points));
    const std::int64_t layer = g.dims[0] * g.dims[1];
    std::uint64_t seq = 0;
    QueryLayers q;
    q.count = g.dims[2];
    q.z = [&g](std::int64_t k) { return g.origin[2] + static_cast<double>(k) * g.spacing[2]; };
    q.positions = [layer](std::int64_t k0, std::int64_t k1) { return static_cast<double>((k1 - k0) * layer); };
    q.bytes = [layer](std::int64_t k0, std::int64_t k1) { return 48.0 * static_cast<double>((k1 - k0) * layer); };
    q.source = [&g, layer](std::int64_t k0, std::int64_t k1) { return std::make_unique<GridRasterSource>(g, k0 * layer, k1 * layer); };
    q.accept = [&](BatchBuffer& buf, std::int64_t, std::int64_t) { buf.forward(sink, seq); };
    // the x-y extent of the samples, as GridRasterSource places them
    const std::array<Vec3, 2> xy = {Vec3{g.origin[0], g.origin[1], 0},
                                    Vec3{g.origin[0] + static_cast<double>(g.dims[0] - 1) * g.spacing[0],
                                         g.origin[1] + static_cast<double>(g.dims[1] - 1) * g.spacing[1], 0}};
    const FieldQueryStats st = run_query_slabs(store, plan, p, xy, q, run, rep);
    if (run.evaluated) run.evaluated(st);
    sink.finish();
    if (report) *report = rep;
    return st;
}

namespace {

/// The field (value, and gradient when want_grad) at every position of `at`, in its order:
/// the positions taken in z order (stable) slab by slab, those of one z in one slab.
struct PositionResults {
    std::vector<double> value;
    std::vector<Vec3> grad;
    FieldQueryStats stats;
};

PositionResults evaluate_positions(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                   const std::vector<Vec3>& at, bool want_grad, const FieldQueryRun& run, StoreQueryReport& rep) {
    const std::size_t n = at.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&at](std::size_t a, std::size_t b) { return at[a].z < at[b].z; });
    // the layers: runs of equal z (a slice's pixel rows), so that a slab never splits one
    std::vector<std::size_t> start{0};
    for (std::size_t k = 1; k < n; ++k)
        if (at[order[k]].z != at[order[k - 1]].z) start.push_back(k);
    start.push_back(n);
    PositionResults r;
    r.value.assign(n, std::numeric_limits<double>::quiet_NaN());
    r.grad.assign(want_grad ? n : 0, Vec3{});
    const auto first = [&start](std::int64_t k) { return start[static_cast<std::size_t>(k)]; };
    QueryLayers q;
    q.count = static_cast<std::int64_t>(start.size() - 1);
    q.z = [&](std::int64_t k) { return at[order[first(k)]].z; };
    q.positions = [&](std::int64_t k0, std::int64_t k1) { return static_cast<double>(first(k1) - first(k0)); };
    q.bytes = [&](std::int64_t k0, std::int64_t k1) { return 64.0 * static_cast<double>(first(k1) - first(k0)); };
    q.source = [&](std::int64_t k0, std::int64_t k1) {
        std::vector<Vec3> part;
        part.reserve(first(k1) - first(k0));
        for (std::size_t k = first(k0); k < first(k1); ++k) part.push_back(at[order[k]]);
        return std::make_unique<QueryListSource>(std::move(part), want_grad);
    };
    q.accept = [&](BatchBuffer& buf, std::int64_t k0, std::int64_t) {
        std::size_t k = first(k0);
        for (const Batch& b : buf.batches)
            for (std::size_t j = 0; j < b.query.value.size(); ++j, ++k) {
                r.value[order[k]] = b.query.value[j];
                if (want_grad) r.grad[order[k]] = b.query.grad[j];
            }
        buf.batches.clear();
    };
    std::array<Vec3, 2> xy = {Vec3{kUnbounded, kUnbounded, 0}, Vec3{-kUnbounded, -kUnbounded, 0}};
    for (const Vec3& x : at) {
        xy[0].x = std::min(xy[0].x, x.x);
        xy[0].y = std::min(xy[0].y, x.y);
        xy[1].x = std::max(xy[1].x, x.x);
        xy[1].y = std::max(xy[1].y, x.y);
    }
    r.stats = run_query_slabs(store, plan, p, xy, q, run, rep);
    if (run.evaluated) run.evaluated(r.stats);
    return r;
}

/// The results as the in-memory graph's batches (kQueriesPerBatch positions each, in order) to `sink`.
void emit_results(const std::vector<Vec3>& at, const PositionResults& r, bool want_grad, Sink& sink) {
    std::uint64_t seq = 0;
    for (std::size_t b0 = 0; b0 < at.size(); b0 += kQueriesPerBatch) {
        const std::size_t b1 = std::min(at.size(), b0 + kQueriesPerBatch);
        const auto from = static_cast<std::ptrdiff_t>(b0), to = static_cast<std::ptrdiff_t>(b1);
        Batch b;
        b.seq = seq++;
        b.kind = RecordKind::query;
        b.query.want_grad = want_grad;
        b.query.at.assign(at.begin() + from, at.begin() + to);
        b.query.value.assign(r.value.begin() + from, r.value.begin() + to);
        if (want_grad) b.query.grad.assign(r.grad.begin() + from, r.grad.begin() + to);
        sink.consume(std::move(b));
    }
}

}  // namespace

FieldQueryStats probe_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                  std::vector<Vec3> at, const std::string& csv, const FieldQueryRun& run, StoreQueryReport* report) {
    StoreQueryReport rep;
    ProbeCsvSink sink(csv);
    const PositionResults r = evaluate_positions(store, plan, p, at, /*want_grad=*/true, run, rep);
    emit_results(at, r, true, sink);
    sink.finish();
    if (report) *report = rep;
    return r.stats;
}

SliceResult slice_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                              const PlaneRaster& raster, const SliceRequest& req, const FieldQueryRun& run, StoreQueryReport* report) {
    StoreQueryReport rep;
    std::vector<Vec3> at;
    at.reserve(static_cast<std::size_t>(raster.width) * static_cast<std::size_t>(raster.height));
    for (int row = 0; row < raster.height; ++row)
        for (int col = 0; col < raster.width; ++col) at.push_back(raster.position(row, col));
    const PositionResults r = evaluate_positions(store, plan, p, at, /*want_grad=*/false, run, rep);
    SliceImageSink sink(raster.width, raster.height, req.colormap, req.range[0], req.range[1]);
    emit_results(at, r, false, sink);
    at = {};
    // the data points near the plane, brick by brick
    SliceResult out;
    out.queries = r.stats;
    out.near = req.near ? *req.near : half_spacing(plan.frame.bounds, plan.frame.points);
    PointSet near;
    std::vector<double> raw;
    for (std::size_t i = 0; i < store.bricks().size(); ++i) {
        const PointBrickEntry& b = store.bricks()[i];
        const auto a = static_cast<std::size_t>(raster.axis);
        if (b.lo[a] > raster.at + out.near || b.hi[a] < raster.at - out.near) continue;
        store.read_brick(i, raw);
        for (std::size_t k = 0; k < raw.size(); k += 4)
            if (std::abs(raw[k + a] - raster.at) <= out.near) near.pos.push_back(Vec3{raw[k], raw[k + 1], raw[k + 2]});
    }
    finish_slice(sink.image(), near, raster, req, out);
    if (report) *report = rep;
    return out;
}

void print_store_query_stats(std::FILE* out, const char* cmd, const ScatteredStorePlan& plan, const StoreQueryReport& r) {
    std::fprintf(out,
                 "%s: point store in %d slabs (%d built again), halo up to %g world units, at most %llu of %llu points loaded at "
                 "once (%llu in all), %llu locals (%llu fits copied from the slab before, %llu regularised), largest slab field "
                 "%.1f MiB; time: plan %.3f s, read %.3f s, field %.3f s, queries %.3f s\n",
                 cmd, r.slabs, r.retries, r.halo, static_cast<unsigned long long>(r.most_loaded),
                 static_cast<unsigned long long>(plan.frame.points), static_cast<unsigned long long>(r.loaded),
                 static_cast<unsigned long long>(r.field.locals), static_cast<unsigned long long>(r.reused_fits),
                 static_cast<unsigned long long>(r.field.regularised), static_cast<double>(r.field.memory_bytes) / 1048576.0,
                 plan.seconds, r.read_seconds, r.field_seconds, r.query_seconds);
}

}  // namespace meshless
