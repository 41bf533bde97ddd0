// A pass-through stage that reports how many records each batch carries (Batch::count()) to a
// callback, for progress lines (cli/progress_meter.hpp). Put it where the batches' records measure
// the work (query positions before evaluation, seeds before projection). The callback is called
// concurrently from the stages' threads and must be thread-safe; the stage changes nothing.
#pragma once
#include <functional>
#include <utility>

#include "stream/stage.hpp"

namespace meshless {

class ProgressStage final : public Stage {
public:
    explicit ProgressStage(std::function<void(double)> report) : report_(std::move(report)) {}
    void process(Batch& b) const override {
        if (report_) report_(static_cast<double>(b.count()));
    }

private:
    std::function<void(double)> report_;
};

}  // namespace meshless
