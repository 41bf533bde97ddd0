// A sink adaptor that removes near-duplicate points (kernels/point_dedup.hpp) from the batches
// it receives, in sequence order, and hands the rest to the next sink (--dedup on the
// scattered-data isosurface). Block ids (Batch::point_block) follow the points that stay. Runs on
// the runner's serial sink side, so the result does not depend on the thread count; a picture
// drawn from the stream must then be drawn by the sink (not in the parallel stages), after the
// removal. Memory: that of PointDedup (the kept points). Not thread-safe (the runner calls it
// serially).
#pragma once
#include "kernels/point_dedup.hpp"
#include "stream/stage.hpp"

namespace meshless {

class DedupSink final : public Sink {
public:
    PayloadSet takes() const override { return next_.takes(); }
    DedupSink(Sink& next, double fraction, double cell) : next_(next), dedup_(fraction, cell) {}
    void consume(Batch&& b) override;
    void finish() override { next_.finish(); }
    std::int64_t removed() const { return dedup_.removed(); }

private:
    Sink& next_;
    PointDedup dedup_;
};

}  // namespace meshless
