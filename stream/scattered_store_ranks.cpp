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

std::vector<std::int64_t> store_rank_starts(const ScatteredStorePlan& plan, int ranks, double reach) {
    if (ranks < 1) throw std::invalid_argument("store_rank_starts: bad rank count");
    const std::int64_t layers = stencil_count(plan.grid.dims[2]);
    const auto loaded = [&](std::int64_t a, std::int64_t b) { return store_layers_loaded(plan, a, b, reach); };
    // the ranges of at most `most` points loaded, greedily from the first layer: their starts
    const auto cut = [&](std::uint64_t most) {
        std::vector<std::int64_t> starts;
        for (std::int64_t a = 0; a < layers;) {
            starts.push_back(a);
            std::int64_t b = a + 1;
            while (b < layers && loaded(a, b + 1) <= most) ++b;
            a = b;
        }
        return starts;
    };
    // the least `most` that `ranks` ranges reach (a range holds one layer at least)
    std::uint64_t lo = 0, hi = loaded(0, layers);
    for (std::int64_t a = 0; a < layers; ++a) lo = std::max(lo, loaded(a, a + 1));
    while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (cut(mid).size() <= static_cast<std::size_t>(ranks)) hi = mid;
        else lo = mid + 1;
    }
    std::vector<std::int64_t> starts = layers > 0 ? cut(lo) : std::vector<std::int64_t>{};
    // ranks left over: split the widest ranges (a part of a range loads no more than the range)
    while (starts.size() < static_cast<std::size_t>(ranks)) {
        std::size_t widest = 0;
        std::int64_t width = 0;
        for (std::size_t i = 0; i < starts.size(); ++i) {
            const std::int64_t w = (i + 1 < starts.size() ? starts[i + 1] : layers) - starts[i];
            if (w > width) {
                width = w;
                widest = i;
            }
        }
        if (width < 2) break;  // (more ranks than layers)
        starts.insert(starts.begin() + static_cast<std::ptrdiff_t>(widest) + 1, starts[widest] + width / 2);
    }
    while (starts.size() < static_cast<std::size_t>(ranks)) starts.push_back(layers);  // (idle ranks: empty ranges at the end)
    return starts;
}

std::array<std::int64_t, 2> store_layers_of_rank(const ScatteredStorePlan& plan, int rank, int ranks, double reach) {
    if (ranks < 1 || rank < 0 || rank >= ranks) throw std::invalid_argument("store_layers_of_rank: bad rank");
    const std::vector<std::int64_t> starts = store_rank_starts(plan, ranks, reach);
    const std::int64_t layers = stencil_count(plan.grid.dims[2]);
    const auto r = static_cast<std::size_t>(rank);
    return {starts[r], r + 1 < starts.size() ? starts[r + 1] : layers};
}

StoreRankResult run_scattered_store_rank(const PointStore& store, const ScatteredStorePlan& plan, const FieldParams& field_params,
                                         ScatteredStoreParams sp, double iso, int n, const FieldProjectParams& np, double dedup,
                                         int rank, int ranks, RankChannel& channel, Sink* out, const RunOptions& opt,
                                         const std::function<void(double)>& progress) {
    if (rank == 0 && !out) throw std::invalid_argument("run_scattered_store_rank: rank 0 needs a sink");
    StoreRankResult res;
    res.layers = store_layers_of_rank(plan, rank, ranks, store_slab_reach(plan, field_params, np));
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
