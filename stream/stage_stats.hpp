// Thread-safe accumulators for the statistics stages report (counts only; relaxed atomics). A stage
// adds the counts of one batch after processing it; stats() may be read once the run is over.
#pragma once
#include <atomic>

#include "kernels/cell_sampling.hpp"
#include "kernels/project_sample.hpp"

namespace meshless {

class AtomicSamplingStats {
public:
    void add(const SamplingStats& s) {
        active_ += s.active_cells;
        nonfinite_ += s.nonfinite_cells;
    }
    SamplingStats load() const { return {active_.load(), nonfinite_.load()}; }

private:
    std::atomic<std::int64_t> active_{0}, nonfinite_{0};
};

class AtomicProjectionStats {
public:
    void add(const ProjectionStats& s) {
        input_ += s.input;
        output_ += s.output;
        too_far_ += s.too_far;
        flat_ += s.flat;
        missed_ += s.missed;
    }
    ProjectionStats load() const {
        ProjectionStats s;
        s.input = input_.load();
        s.output = output_.load();
        s.too_far = too_far_.load();
        s.flat = flat_.load();
        s.missed = missed_.load();
        return s;
    }

private:
    std::atomic<std::int64_t> input_{0}, output_{0}, too_far_{0}, flat_{0}, missed_{0};
};

}  // namespace meshless
