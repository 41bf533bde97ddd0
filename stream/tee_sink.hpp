// A sink that hands every batch to two sinks (e.g. a PLY writer and the splat sink of
// `meshless isosurface -o out.ply --png out.png`): nothing is collected; memory = one extra copy of
// the batch in flight. finish() finishes the first sink, then the second, so the order of the
// constructor is the order of commits (put the one that can fail without side effects first).
// Throws what the sinks throw. Not thread-safe (Sink rules).
#pragma once
#include "stream/stage.hpp"

namespace meshless {

class TeeSink final : public Sink {
public:
    TeeSink(Sink& first, Sink& second) : first_(first), second_(second) {}
    void consume(Batch&& b) override {
        Batch copy = b;
        first_.consume(std::move(copy));
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
