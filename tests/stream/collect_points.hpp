// A sink for the stream tests that keeps every point it is given, in order, and whether finish() came.
#pragma once
#include <vector>

#include "stream/stage.hpp"

namespace meshless::test {

struct CollectPoints final : Sink {
    PayloadSet takes() const override { return Payload::points; }
    std::vector<PointRecord> points;
    bool finished = false;
    void consume(Batch&& b) override { points.insert(points.end(), b.points.begin(), b.points.end()); }
    void finish() override { finished = true; }
};

}  // namespace meshless::test
