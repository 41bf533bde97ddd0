// Generate and project fused into one stage (dissertation sections 3.3-3.5, paradigm C in one
// process): a batch naming cell rows becomes a batch of projected points without materialising the
// 88-byte SampleRecords. Bytes equal GenerateStage followed by ProjectStage (same record, same
// projection), which the tests check; `meshless isosurface` uses it, the piped stages do not.
// Thread-safe: statistics are atomics.
#pragma once
#include <atomic>

#include "kernels/cell_sampling.hpp"
#include "stream/stage.hpp"

namespace meshless {

class GenerateProjectStage final : public Stage {
public:
    /// The volume must outlive the stage.
    GenerateProjectStage(VolumeView v, double iso, SamplingParams p, Projection mode)
        : v_(v), iso_(iso), p_(p), mode_(mode) {}
    void process(Batch& b) const override;
    SamplingStats sampling_stats() const { return {active_.load(), nonfinite_.load()}; }
    ProjectionStats projection_stats() const;

private:
    VolumeView v_;
    double iso_;
    SamplingParams p_;
    Projection mode_;
    mutable std::atomic<std::int64_t> active_{0}, nonfinite_{0};
    mutable std::atomic<std::int64_t> input_{0}, output_{0}, too_far_{0}, flat_{0}, missed_{0};
};

}  // namespace meshless
