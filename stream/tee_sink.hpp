// A sink that hands every batch to two sinks (e.g. the splat sink and a PLY writer of
// `meshless isosurface -o out.ply --png out.png`): nothing is collected. The first sink observes
// the batch (Sink::observe: no copy when it only reads it), the second consumes it. finish() finishes the first sink, then the second, so the order of the
// constructor is the order of commits (put the one that can fail without side effects first).
// Throws what the sinks throw. Not thread-safe (Sink rules).
#pragma once
#include "stream/stage.hpp"

namespace meshless {

class TeeSink final : public Sink {
public:
    TeeSink(Sink& first, Sink& second) : first_(first), second_(second) {}
    void consume(Batch&& b) override {
        first_.observe(b);  // no copy when the first sink only reads (SplatSink)
        second_.consume(std::move(b));
    }
    void finish() override {
        first_.finish();
        second_.finish();
    }

private:
    Sink& first_;
    Sink& second_;
};

}  // namespace meshless
