// A sink that hands every batch to two sinks (e.g. the splat sink and a PLY writer of
// `meshless isosurface -o out.ply --png out.png`): nothing is collected. The first sink observes
// the batch (Sink::observe: no copy when it only reads it), the second consumes it. finish() finishes the first sink, then the second, so the order of the
// constructor is the order of commits (put the one that can fail without side effects first).
// A branch whose reader has gone (it throws BrokenPipe: `-o - | head`) is dropped and the other
// one fed to the end, as `tee -p` does: the named file is still complete. finish() then rethrows
// that BrokenPipe (the CLI exits quietly) after finishing the live branch; when both branches
// have closed, the BrokenPipe propagates at once.
// Throws what the sinks throw. Not thread-safe (Sink rules).
#pragma once
#include <exception>
#include <utility>

#include "kernels/errors.hpp"
#include "stream/stage.hpp"

namespace meshless {

class TeeSink final : public Sink {
public:
    PayloadSet takes() const override { return first_.takes() & second_.takes(); }
    TeeSink(Sink& first, Sink& second) : first_(first), second_(second) {}
    void consume(Batch&& b) override {
        if (live_[0]) guarded(0, [&] { first_.observe(b); });  // no copy when the first sink only reads (SplatSink)
        if (live_[1]) guarded(1, [&] { second_.consume(std::move(b)); });
    }
    void finish() override {  // a sink writing stdout may meet the closed pipe only here
        if (live_[0]) guarded(0, [&] { first_.finish(); });
        if (live_[1]) guarded(1, [&] { second_.finish(); });
        if (closed_) std::rethrow_exception(closed_);
    }
    /// False once branch i (0 = first, 1 = second) threw BrokenPipe.
    bool live(int i) const { return live_[i]; }

private:
    template <class F>
    void guarded(int i, F&& f) {
        try {
            f();
        } catch (const BrokenPipe&) {
            live_[i] = false;
            closed_ = std::current_exception();
            if (!live_[0] && !live_[1]) throw;
        }
    }
    Sink& first_;
    Sink& second_;
    bool live_[2] = {true, true};
    std::exception_ptr closed_;
};

}  // namespace meshless
