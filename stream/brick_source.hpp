// Out-of-core paradigm (C) over a brick store (dissertation section 3.6, Morton-ordered bricks):
// BrickSource yields, for each active brick in Morton order, batches naming the brick and a range
// of its cell rows (at most kMaxBatchRecords cells each); BrickGenerateStage fetches the brick
// through the byte-budgeted BrickCache and samples (and, fused, projects) its cells. Only active
// bricks are read; memory is the cache budget plus the batches in flight. Batch boundaries depend
// only on the store and the isovalue, so outputs are identical for any thread count, and a range of
// the active bricks (an MPI rank's share) yields exactly the corresponding slice of the output.
#pragma once
#include <cstddef>
#include <optional>
#include <vector>

#include "ooc/brick_cache.hpp"
#include "stream/stage.hpp"
#include "stream/stage_stats.hpp"

namespace meshless {

class BrickSource final : public Source {
public:
    Payload gives() const override { return Payload::cells; }
    /// bricks: indices into store.bricks(), in the order to emit (Morton order for whole runs).
    BrickSource(const BrickStore& store, std::vector<std::size_t> bricks);
    std::optional<Batch> next() override;

private:
    const BrickStore& store_;
    std::vector<std::size_t> bricks_;
    std::size_t at_ = 0;
    std::int64_t row_ = 0;
    std::uint64_t seq_ = 0;
};

class BrickGenerateStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::cells; }
    Payload gives(Payload) const override { return fused_ ? Payload::points : Payload::samples; }
    /// fused: project at once with `mode` (points out); nullopt: emit samples (as `generate`).
    BrickGenerateStage(const BrickStore& store, BrickCache& cache, double iso, SamplingParams p,
                       std::optional<Projection> fused)
        : store_(store), cache_(cache), iso_(iso), p_(p), fused_(fused) {}
    void process(Batch& b) const override;
    SamplingStats sampling_stats() const { return sampling_.load(); }
    ProjectionStats projection_stats() const { return projection_.load(); }

private:
    const BrickStore& store_;
    BrickCache& cache_;
    double iso_;
    SamplingParams p_;
    std::optional<Projection> fused_;
    mutable AtomicSamplingStats sampling_;
    mutable AtomicProjectionStats projection_;
};

}  // namespace meshless
