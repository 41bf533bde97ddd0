// The "project" stage (dissertation section 3.3): sample batches in, point batches out, by
// kernels/project_sample.hpp (approx Newton step, exact cubic, or none). Thread-safe; statistics
// are atomics.
#pragma once
#include "stream/stage.hpp"
#include "stream/stage_stats.hpp"

namespace meshless {

class ProjectStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::samples; }
    Payload gives(Payload) const override { return Payload::points; }
    ProjectStage(double iso, Projection mode) : iso_(iso), mode_(mode) {}
    void process(Batch& b) const override;
    ProjectionStats stats() const { return stats_.load(); }

private:
    double iso_;
    Projection mode_;
    mutable AtomicProjectionStats stats_;
};

}  // namespace meshless
