// Generate and project fused into one stage (dissertation sections 3.3-3.5, paradigm C in one
// process): a batch naming cell rows becomes a batch of projected points without materialising the
// 88-byte SampleRecords. Bytes equal GenerateStage followed by ProjectStage (same record, same
// projection), which the tests check; `meshless isosurface` uses it, the piped stages do not.
// Thread-safe: statistics are atomics.
#pragma once
#include "stream/stage.hpp"
#include "stream/stage_stats.hpp"

namespace meshless {

class GenerateProjectStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::cells; }
    Payload gives(Payload) const override { return Payload::points; }
    /// The volume must outlive the stage. Batches carrying a chunk (stream/slab_source.hpp) are
    /// sampled from the chunk instead; for a run made only of those, v needs no data (grid and type).
    GenerateProjectStage(VolumeView v, double iso, SamplingParams p, Projection mode)
        : v_(v), iso_(iso), p_(p), mode_(mode) {}
    void process(Batch& b) const override;
    SamplingStats sampling_stats() const { return sampling_.load(); }
    ProjectionStats projection_stats() const { return projection_.load(); }

private:
    VolumeView v_;
    double iso_;
    SamplingParams p_;
    Projection mode_;
    mutable AtomicSamplingStats sampling_;
    mutable AtomicProjectionStats projection_;
};

}  // namespace meshless
