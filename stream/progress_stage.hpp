// A pass-through stage that reports the work each batch carries to a callback, for progress lines
// (cli/progress_meter.hpp). By default the work is the batch's records (Batch::count()): put it
// where records measure the work (query positions before evaluation, seeds before projection).
// With work_units as the measure it counts what a generating source hands out (cell rows, cell
// layers, block cells, stencils: Batch::cells; a brick for a brick batch without a cell range):
// put it first, before the stage that turns the work into records. The callback is called
// concurrently from the stages' threads and must be thread-safe; the stage changes nothing.
#pragma once
#include <functional>
#include <string>
#include <utility>

#include "stream/stage.hpp"

namespace meshless {

/// A front end's progress display of `total` work units named `unit` ("cells", "stencils"): returns
/// the function that counts units done (any thread); the display lives as long as that function.
using ProgressCounter = std::function<std::function<void(double)>(const std::string& unit, double total)>;

/// The work a source's batch describes: cells.k1 - cells.k0 when it has a cell range, else 1 for
/// a brick batch (brick >= 0), else its records.
inline double work_units(const Batch& b) {
    if (b.cells.k1 > b.cells.k0) return static_cast<double>(b.cells.k1 - b.cells.k0);
    if (b.brick >= 0) return 1;
    return static_cast<double>(b.count());
}

class ProgressStage final : public Stage {
public:
    PayloadSet takes() const override { return PayloadSet::any(); }
    Payload gives(Payload given) const override { return given; }
    using Measure = double (*)(const Batch&);
    explicit ProgressStage(std::function<void(double)> report, Measure measure = nullptr)
        : report_(std::move(report)), measure_(measure) {}
    void process(Batch& b) const override {
        if (report_) report_(measure_ ? measure_(b) : static_cast<double>(b.count()));
    }

private:
    std::function<void(double)> report_;
    Measure measure_;
};

}  // namespace meshless
