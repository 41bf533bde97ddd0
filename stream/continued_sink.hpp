// Several graph runs into one set of outputs (`isosurface`/`generate VOLUME --iso V1,V2,...`: one
// run per isovalue, the points of each run after the previous run's): a sink that continues the
// batches' sequence numbers from one run to the next and leaves the real sink's finish() to the
// caller. Dissertation: none (the front end around chapter 3's isosurfaces). Throws what the runs
// and the sink throw.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "stream/stage.hpp"

namespace meshless {

/// Hands batches on to `to` with their sequence numbers continued from one graph run to the next,
/// and leaves its finish() to the caller: the runs of several isovalues into one set of outputs.
class ContinuedSink final : public Sink {
public:
    PayloadSet takes() const override { return to_.takes(); }
    explicit ContinuedSink(Sink& to) : to_(to) {}
    void consume(Batch&& b) override {
        b.seq = next(b.seq);
        points_ += b.points.size();
        to_.consume(std::move(b));
    }
    void observe(const Batch& b) override {
        Batch copy = b;
        consume(std::move(copy));
    }
    void finish() override {  // the next run's batches follow this one's
        base_ = end_;
        last_points_ = points_;
        points_ = 0;
    }
    /// The points of the run that finished last.
    std::size_t last_run_points() const { return last_points_; }

private:
    std::uint64_t next(std::uint64_t seq) {
        end_ = std::max(end_, base_ + seq + 1);
        return base_ + seq;
    }
    Sink& to_;
    std::uint64_t base_ = 0, end_ = 0;
    std::size_t points_ = 0, last_points_ = 0;
};

/// The runs of a job's isovalues into one sink: run(i, sink) for each in turn (sequence numbers
/// continued), the sink finished after the last; r[i] and counts[i] receive each run's result and
/// points. Returns the first run's result.
template <class Result, class Run>
Result run_each_isovalue(std::size_t n, Sink& sink, std::vector<Result>& r, std::vector<std::size_t>& counts,
                        const Run& run) {
    r.assign(n, {});
    counts.assign(n, 0);
    ContinuedSink continued(sink);
    for (std::size_t i = 0; i < n; ++i) {
        r[i] = run(i, continued);
        counts[i] = continued.last_run_points();
    }
    sink.finish();
    return r[0];
}

}  // namespace meshless
