// A progress line on stderr for runs longer than about a second (Unix habits):
//   "meshless slice: 42% 1.31 M/s, ETA 0:07"
// shown only when enabled (stderr is a terminal and no --quiet: progress_wanted()), first after
// `delay` seconds, then at most 4 times a second, and cleared by done() or the destructor. Work is
// counted in units (positions, bricks, records) against a known total; add() is thread-safe (an
// atomic counter; one thread at a time draws, the others skip), so stages running concurrently can
// report. The clock and the output stream are parameters for the tests; MESHLESS_PROGRESS=always
// forces the line on (no terminal needed, no first-second delay) for logs and the CLI tests.
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>

#include "cli/args.hpp"
#include "stream/progress_stage.hpp"

namespace meshless::cli {

/// Declares --quiet (no progress line) on a command that shows progress.
void add_quiet_option(Args& a);
/// stderr is a terminal and --quiet (when declared) was not given; or MESHLESS_PROGRESS=always in
/// the environment (logs, tests) and no --quiet.
bool progress_wanted(const Args& a);
/// The seconds before the first line: 1, or 0 with MESHLESS_PROGRESS=always.
double progress_delay();
/// Seconds as a clock, "m:ss" or "h:mm:ss" (the ETA of a progress line).
std::string progress_clock_text(double seconds);

class ProgressMeter {
public:
    using Clock = std::function<double()>;  ///< seconds, monotonic
    /// `label` heads the line ("meshless slice"); `unit` names the rate ("positions"); total > 0.
    ProgressMeter(std::string label, std::string unit, double total, bool enabled, double delay = 1.0,
                  std::FILE* out = stderr, Clock clock = {});
    ~ProgressMeter();
    ProgressMeter(const ProgressMeter&) = delete;
    ProgressMeter& operator=(const ProgressMeter&) = delete;

    /// `units` more done (any thread).
    void add(double units);
    /// Sets the fraction done (0..1) directly (single-threaded producers such as convert).
    void set_fraction(double f);
    /// Clears the line (idempotent).
    void done();
    /// A progress meter of a command: "meshless COMMAND" heads the line, enabled and delayed as
    /// progress_wanted(a) and progress_delay() say.
    static ProgressMeter of(const Args& a, std::string unit, double total);

    /// The total (given at construction, or by set_total).
    double total() const { return total_.load(std::memory_order_relaxed); }
    /// Sets the total when it is known only once the work has started (any thread; > 0).
    void set_total(double total);
    /// Units done so far (0 when disabled: a disabled meter counts nothing).
    double done_units() const { return done_milli_.load() / 1000.0; }
    /// The line drawn for `done` of the total after `elapsed` seconds (no "\r"): exposed for tests.
    std::string line(double done, double elapsed) const;

private:
    void maybe_draw();
    std::string label_, unit_;
    std::atomic<double> total_;
    bool enabled_;
    double delay_;
    std::FILE* out_;
    Clock clock_;
    double start_;
    std::atomic<std::uint64_t> done_milli_{0};  ///< units x 1000 (fractional units from set_fraction)
    std::mutex draw_;
    double last_draw_ = -1;
    bool drawn_ = false;
};

/// The progress displays of a command for a recipe (stream/progress_stage.hpp ProgressCounter): a
/// ProgressMeter::of(a, unit, total) for each, cleared when the recipe lets go of its counter.
ProgressCounter progress_counter(const Args& a);

}  // namespace meshless::cli
