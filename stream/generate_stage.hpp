// The "generate" stage of paradigm (C) (dissertation sections 3.4-3.5): turns a batch naming cell
// rows into one SampleRecord per active cell (kernels/cell_sampling.hpp). Thread-safe: statistics
// are accumulated under a mutex-free atomic per field.
#pragma once
#include <atomic>

#include "kernels/cell_sampling.hpp"
#include "stream/stage.hpp"

namespace meshless {

class GenerateStage final : public Stage {
public:
    /// The volume must outlive the stage.
    GenerateStage(VolumeView v, double iso, SamplingParams p = {}) : v_(v), iso_(iso), p_(p) {}
    void process(Batch& b) const override;
    SamplingStats stats() const { return {active_.load(), nonfinite_.load()}; }

private:
    VolumeView v_;
    double iso_;
    SamplingParams p_;
    mutable std::atomic<std::int64_t> active_{0}, nonfinite_{0};
};

}  // namespace meshless
