// Ctrl-C during a long call of the Python module (python/README.md): the library's work runs on a
// thread of its own while the calling thread, the GIL released, waits for it and looks for a
// pending signal every kSignalPoll (PyErr_CheckSignals with the GIL held: Python's own handler has
// run by then). On KeyboardInterrupt (or any exception a signal handler raises) it sets `stop`,
// which a StopSink between the graph and its sink turns into a Stopped exception at the graph's
// next batch (the runner then drains the batches in flight, stage and sink destructors free
// everything, the graph's temporary files go with their objects), waits for the work to end and
// raises the signal's exception. Outside the main thread Python delivers no signals and the call
// just waits. The work's own exceptions are rethrown unchanged in the calling thread.
// Thread-safety: `stop` is the only state shared with the work.
#pragma once
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>

#include "stream/stage.hpp"

namespace meshless::python {

inline constexpr std::chrono::milliseconds kSignalPoll{50};

/// Thrown by StopSink once `stop` is set: the graph ends at that batch.
struct Stopped : std::exception {
    const char* what() const noexcept override { return "stopped"; }
};

/// Forwards to `sink`, and throws Stopped before a batch once `stop` is set.
class StopSink final : public Sink {
public:
    PayloadSet takes() const override { return sink_.takes(); }
    StopSink(Sink& sink, const std::atomic<bool>& stop) : sink_(sink), stop_(stop) {}
    void consume(Batch&& b) override {
        if (stop_.load(std::memory_order_relaxed)) throw Stopped{};
        sink_.consume(std::move(b));
    }
    void observe(const Batch& b) override {
        if (stop_.load(std::memory_order_relaxed)) throw Stopped{};
        sink_.observe(b);
    }
    void finish() override { sink_.finish(); }

private:
    Sink& sink_;
    const std::atomic<bool>& stop_;
};

/// Runs work(stop) as described above; called with the GIL held. Throws pybind11::error_already_set
/// for a signal's exception, or what work threw.
void run_interruptible(const std::function<void(const std::atomic<bool>& stop)>& work);

}  // namespace meshless::python
