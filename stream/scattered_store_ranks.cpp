#include "stream/scattered_store_ranks.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "kernels/marching_stencils.hpp"
#include "stream/dedup_sink.hpp"
#include "stream/stencil_ranks.hpp"

namespace meshless {

namespace {

/// Tags every batch with one unit (this rank's) before the rank sink takes it.
class UnitTagSink final : public Sink {
public:
    UnitTagSink(Sink& next, UnitTags& tags, std::size_t unit) : next_(next), tags_(tags), unit_(unit) {}
    PayloadSet takes() const override { return next_.takes(); }
    void consume(Batch&& b) override {
        tags_.push(unit_);
        next_.consume(std::move(b));
    }
    void finish() override { next_.finish(); }

private:
    Sink& next_;
    UnitTags& tags_;
    std::size_t unit_;
};

}  // namespace

std::array<std::int64_t, 2> store_layers_of_rank(const ScatteredStorePlan& plan, int rank, int ranks) {
    if (ranks < 1 || rank < 0 || rank >= ranks) throw std::invalid_argument("store_layers_of_rank: bad rank");
    const std::int64_t cells = plan.grid.dims[2];
    const std::int64_t layers = stencil_count(cells);
    // the points a stencil layer's cells hold (layer m: cells 2m .. 2m+2, the last one to the end)
    std::vector<double> cum(static_cast<std::size_t>(layers) + 1, 0.0);
    for (std::int64_t m = 0; m < layers; ++m) {
        double w = 1;  // (empty layers still cost their stencils)
        const std::int64_t k1 = m + 1 == layers ? cells : 2 * m + 2;
        for (std::int64_t k = 2 * m; k < k1 && k < static_cast<std::int64_t>(plan.layer_points.size()); ++k)
            w += static_cast<double>(plan.layer_points[static_cast<std::size_t>(k)]);
        cum[static_cast<std::size_t>(m) + 1] = cum[static_cast<std::size_t>(m)] + w;
    }
    // rank r starts at the first layer whose cumulative share reaches r / ranks
    const auto start = [&](int r) -> std::int64_t {
        if (r <= 0) return 0;
        if (r >= ranks) return layers;
        const double want = cum.back() * static_cast<double>(r) / static_cast<double>(ranks);
        return static_cast<std::int64_t>(std::lower_bound(cum.begin(), cum.end(), want) - cum.begin());
    };
    const std::int64_t a = std::min(start(rank), layers), b = std::min(start(rank + 1), layers);
    return {a, std::max(a, b)};
}

StoreRankResult run_scattered_store_rank(const PointStore& store, const ScatteredStorePlan& plan, const FieldParams& field_params,
                                         ScatteredStoreParams sp, double iso, int n, const FieldProjectParams& np, double dedup,
                                         int rank, int ranks, RankChannel& channel, Sink* out, const RunOptions& opt,
                                         const std::function<void(double)>& progress) {
    if (rank == 0 && !out) throw std::invalid_argument("run_scattered_store_rank: rank 0 needs a sink");
    StoreRankResult res;
    res.layers = store_layers_of_rank(plan, rank, ranks);
    sp.layers = res.layers;
    UnitTags tags;
    const auto unit = static_cast<std::size_t>(rank);
    if (rank == 0) {
        std::optional<DedupSink> dedup_sink;  // (rank 0's side, over the merged stream)
        if (dedup > 0) dedup_sink.emplace(*out, dedup, 0.1 * plan.grid.diagonal());
        Sink& down = dedup_sink ? static_cast<Sink&>(*dedup_sink) : *out;
        RankMergeSink merge(channel, tags, static_cast<std::size_t>(ranks), [](std::size_t u) { return static_cast<int>(u); }, down);
        UnitTagSink tagged(merge, tags, unit);
        res.stats = run_scattered_store_isosurface(store, plan, field_params, sp, iso, n, np, 0, tagged, opt, progress, &res.report);
        if (dedup_sink) res.stats.dedup_removed = dedup_sink->removed();
    } else {
        RankSendSink send(channel, tags, rank, std::vector<std::size_t>{unit});
        UnitTagSink tagged(send, tags, unit);
        res.stats = run_scattered_store_isosurface(store, plan, field_params, sp, iso, n, np, 0, tagged, opt, progress, &res.report);
    }
    return res;
}

StoreRankResult sum_store_rank_stats(const StoreRankResult& mine, int rank, int ranks,
                                     const std::function<std::vector<std::int64_t>(const std::vector<std::int64_t>&)>& sum_to_root,
                                     std::vector<StoreRankShare>* shares) {
    StencilRankResult sr;
    sr.seeds = mine.stats.seeds;
    sr.newton = mine.stats.newton;
    const StencilRankResult st = sum_stencil_rank_stats(sr, sum_to_root);
    const ScatteredStoreReport& r = mine.report;
    const FieldBuildStats& f = r.field;
    const auto us = [](double s) { return static_cast<std::int64_t>(s * 1e6); };
    const auto i64 = [](std::uint64_t v) { return static_cast<std::int64_t>(v); };
    std::vector<std::int64_t> v = {r.slabs, r.retries, i64(r.loaded), i64(r.reused_fits), i64(f.locals), i64(f.interpolated),
                                   i64(f.regularised), i64(f.linear_fallback), i64(f.polynomial_only), i64(f.capped), i64(f.grown),
                                   i64(f.spanned), us(r.field_seconds), us(r.coverage_seconds), us(r.read_seconds),
                                   us(mine.stats.seed_busy_seconds), us(mine.stats.newton_busy_seconds), mine.stats.dedup_removed};
    const std::size_t fixed = v.size();
    // each rank's own figures at its place (the sum gathers them)
    v.resize(fixed + 4 * static_cast<std::size_t>(ranks), 0);
    const auto at = [&](int k) { return fixed + 4 * static_cast<std::size_t>(rank) + static_cast<std::size_t>(k); };
    v[at(0)] = i64(r.most_loaded);
    v[at(1)] = i64(f.memory_bytes);
    v[at(2)] = static_cast<std::int64_t>(r.halo_cells * 1e3);
    v[at(3)] = i64(mine.peak_rss);
    const std::vector<std::int64_t> s = sum_to_root(v);
    StoreRankResult tot = mine;
    tot.stats.seeds = st.seeds;
    tot.stats.newton = st.newton;
    if (s.size() != v.size()) return tot;  // (not rank 0)
    const auto u64 = [](std::int64_t x) { return static_cast<std::uint64_t>(x); };
    ScatteredStoreReport& t = tot.report;
    t.slabs = static_cast<int>(s[0]);
    t.retries = static_cast<int>(s[1]);
    t.loaded = u64(s[2]);
    t.reused_fits = u64(s[3]);
    FieldBuildStats& tf = t.field;
    tf.locals = u64(s[4]); tf.interpolated = u64(s[5]); tf.regularised = u64(s[6]); tf.linear_fallback = u64(s[7]);
    tf.polynomial_only = u64(s[8]); tf.capped = u64(s[9]); tf.grown = u64(s[10]); tf.spanned = u64(s[11]);
    t.field_seconds = static_cast<double>(s[12]) * 1e-6;
    t.coverage_seconds = static_cast<double>(s[13]) * 1e-6;
    t.read_seconds = static_cast<double>(s[14]) * 1e-6;
    tot.stats.seed_busy_seconds = static_cast<double>(s[15]) * 1e-6;
    tot.stats.newton_busy_seconds = static_cast<double>(s[16]) * 1e-6;
    tot.stats.dedup_removed = s[17];
    t.most_loaded = 0;
    tf.memory_bytes = 0;
    t.halo_cells = 0;
    if (shares) shares->clear();
    for (int q = 0; q < ranks; ++q) {
        const std::size_t b = fixed + 4 * static_cast<std::size_t>(q);
        t.most_loaded = std::max(t.most_loaded, u64(s[b]));
        tf.memory_bytes = std::max(tf.memory_bytes, u64(s[b + 1]));
        t.halo_cells = std::max(t.halo_cells, static_cast<double>(s[b + 2]) * 1e-3);
        if (shares) shares->push_back(StoreRankShare{u64(s[b]), u64(s[b + 3])});
    }
    return tot;
}

}  // namespace meshless
