#include "stream/isosplat_ranks.hpp"

#include <chrono>
#include <stdexcept>
#include <unordered_map>

#include "stream/brick_source.hpp"

namespace meshless {

IsoSplatResult run_isosplat_bricks_rank(const BrickStore& store, BrickCache& cache, const std::vector<std::size_t>& active,
                                        int rank, int ranks, double iso, Projection mode, const SamplingParams& sp,
                                        RankChannel& channel, Sink* out, const RunOptions& opt) {
    if (ranks < 1 || rank < 0 || rank >= ranks) throw std::invalid_argument("run_isosplat_bricks_rank: bad rank");
    if (rank == 0 && !out) throw std::invalid_argument("run_isosplat_bricks_rank: rank 0 needs a sink");
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<std::size_t> units = units_of_rank(active.size(), rank, ranks);
    std::vector<std::size_t> bricks;
    std::unordered_map<std::int64_t, std::size_t> unit_of_brick;
    for (std::size_t u : units) {
        bricks.push_back(active[u]);
        unit_of_brick.emplace(static_cast<std::int64_t>(active[u]), u);
    }
    BrickSource bricks_source(store, std::move(bricks));
    UnitTags tags;
    TaggingSource source(bricks_source, tags, [&](const Batch& b) { return unit_of_brick.at(b.brick); });
    BrickGenerateStage stage(store, cache, iso, sp, mode);
    const Stage* stages[] = {&stage};
    if (rank == 0) {
        RankMergeSink sink(channel, tags, active.size(), ranks, *out);
        run_pipeline(source, stages, sink, opt);
    } else {
        RankSendSink sink(channel, tags, rank, units);
        run_pipeline(source, stages, sink, opt);
    }
    IsoSplatResult r;
    r.sampling = stage.sampling_stats();
    r.projection = stage.projection_stats();
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace meshless
