#include "stream/store_field_queries.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>

#include "kernels/mpu_field.hpp"
#include "stream/available_cpus.hpp"
#include "stream/field_evaluate_stage.hpp"
#include "stream/field_sinks.hpp"
#include "stream/runner.hpp"
#include "stream/seconds_since.hpp"
#include "stream/store_slab.hpp"
#include "stream/store_slab_runner.hpp"

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

/// The query layers slab by slab (stream/store_slab_runner.hpp): each slab's batches evaluated
/// through its field and support test, kept only when the support test read nothing beyond the
/// loaded range, then accepted in order.
FieldQueryStats run_query_slabs(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                const std::array<Vec3, 2>& query_xy, const QueryLayers& q, const FieldQueryRun& run,
                                StoreQueryReport& rep) {
    const int threads = run.threads > 0 ? run.threads : available_cpus();
    FieldQueryStats st;
    SlabLayers layers;
    layers.count = q.count;
    layers.range = [&q](std::int64_t k0, std::int64_t k1) { return std::array<double, 2>{q.z(k0), q.z(k1 - 1)}; };
    layers.bytes = q.bytes;
    layers.run = [&](std::int64_t k0, std::int64_t k1, const MpuField& field, const PointCoverage* coverage) {
        const auto t1 = QueryClock::now();
        BatchBuffer buf(Payload::queries);
        const FieldEvaluateStage evaluate(field, coverage, p.extrapolate);
        const std::unique_ptr<Source> source = q.source(k0, k1);
        const Stage* stages[] = {&evaluate};
        run_pipeline(*source, stages, buf, {threads});
        rep.query_seconds += seconds_since(t1);
        if (coverage && !coverage->part_exact()) return false;
        st.uncovered += evaluate.uncovered();
        st.clamped += evaluate.clamped();
        st.positions += static_cast<std::size_t>(q.positions(k0, k1));
        q.accept(buf, k0, k1);
        if (run.progress) run.progress(q.positions(k0, k1));
        return true;
    };
    for_each_store_slab(store, plan, p, query_xy, layers, threads, rep);
    return st;
}

}  // namespace

StoreQueries open_store_queries(const std::string& path) {
    StoreQueries q;
    q.store = PointStore::open(path);
    // the slabs' counts need no stencils: a grid of about 16 points a cell, at most 128 cells a side
    const double n = static_cast<double>(std::max<std::uint64_t>(1, q.store->info().points));
    const int level = std::clamp(static_cast<int>(std::ceil(std::log2(std::cbrt(n / 16.0)))), 1, 7);
    q.plan = plan_store_field(*q.store, path, level);
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

/// The results as the in-memory graph's batches (kQueriesPerBatch positions each, in order) to `sink`.
void emit_results(const std::vector<Vec3>& at, const StorePositionValues& r, bool want_grad, Sink& sink);

}  // namespace

StorePositionValues evaluate_store_positions(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                             const std::vector<Vec3>& at, bool want_grad, const FieldQueryRun& run,
                                             StoreQueryReport& rep) {
    const std::size_t n = at.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&at](std::size_t a, std::size_t b) { return at[a].z < at[b].z; });
    // the layers: runs of equal z (a slice's pixel rows), so that a slab never splits one
    std::vector<std::size_t> start{0};
    for (std::size_t k = 1; k < n; ++k)
        if (at[order[k]].z != at[order[k - 1]].z) start.push_back(k);
    start.push_back(n);
    StorePositionValues r;
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

namespace {

void emit_results(const std::vector<Vec3>& at, const StorePositionValues& r, bool want_grad, Sink& sink) {
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
    const StorePositionValues r = evaluate_store_positions(store, plan, p, at, /*want_grad=*/true, run, rep);
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
    const StorePositionValues r = evaluate_store_positions(store, plan, p, at, /*want_grad=*/false, run, rep);
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


}  // namespace meshless
