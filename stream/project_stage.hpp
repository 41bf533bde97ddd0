// The "project" stage (dissertation section 3.3): sample batches in, point batches out, by
// kernels/project_sample.hpp (approx Newton step, exact cubic, or none). Thread-safe; statistics
// are atomics.
#pragma once
#include <atomic>

#include "kernels/project_sample.hpp"
#include "stream/stage.hpp"

namespace meshless {

class ProjectStage final : public Stage {
public:
    ProjectStage(double iso, Projection mode) : iso_(iso), mode_(mode) {}
    void process(Batch& b) const override;
    ProjectionStats stats() const;

private:
    double iso_;
    Projection mode_;
    mutable std::atomic<std::int64_t> input_{0}, output_{0}, too_far_{0}, flat_{0}, missed_{0};
};

}  // namespace meshless
