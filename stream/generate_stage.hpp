// The "generate" stage of paradigm (C) (dissertation sections 3.4-3.5): turns a batch naming cell
// rows into one SampleRecord per active cell (kernels/cell_sampling.hpp). Thread-safe: statistics
// are atomics.
#pragma once
#include "stream/stage.hpp"
#include "stream/stage_stats.hpp"

namespace meshless {

class GenerateStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::cells; }
    Payload gives(Payload) const override { return Payload::samples; }
    /// The volume must outlive the stage. Batches carrying a chunk (stream/slab_source.hpp) are
    /// sampled from the chunk instead; for a run made only of those, v needs no data (grid and type).
    GenerateStage(VolumeView v, double iso, SamplingParams p = {}) : v_(v), iso_(iso), p_(p) {}
    void process(Batch& b) const override;
    SamplingStats stats() const { return stats_.load(); }

private:
    VolumeView v_;
    double iso_;
    SamplingParams p_;
    mutable AtomicSamplingStats stats_;
};

}  // namespace meshless
