#include "cli/progress_meter.hpp"

#include <memory>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string_view>

#include "cli/common.hpp"

namespace meshless::cli {

void add_quiet_option(Args& a) { a.flag("quiet", "no progress line on stderr (it is shown only when stderr is a terminal)"); }

ProgressCounter progress_counter(const Args& a) {
    return [&a](const std::string& unit, double total) {
        auto meter = std::make_shared<ProgressMeter>("meshless " + a.command(), unit, total, progress_wanted(a), progress_delay());
        return std::function<void(double)>([meter](double k) { meter->add(k); });
    };
}

namespace {
bool progress_forced() {
    const char* e = std::getenv("MESHLESS_PROGRESS");
    return e && std::string_view(e) == "always";
}
}  // namespace

bool progress_wanted(const Args& a) {
    return (stderr_is_tty() || progress_forced()) && !(a.declared("quiet") && a.has("quiet"));
}

double progress_delay() { return progress_forced() ? 0.0 : 1.0; }

std::string progress_clock_text(double s) {
    const long long t = std::isfinite(s) ? std::llround(std::clamp(s, 0.0, 1e12)) : 0;
    char b[32];
    if (t >= 3600) std::snprintf(b, sizeof b, "%lld:%02lld:%02lld", t / 3600, t / 60 % 60, t % 60);
    else std::snprintf(b, sizeof b, "%lld:%02lld", t / 60, t % 60);
    return b;
}

ProgressMeter ProgressMeter::of(const Args& a, std::string unit, double total) {
    return ProgressMeter("meshless " + a.command(), std::move(unit), total, progress_wanted(a), progress_delay());
}

namespace {
double steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}


std::string rate_text(double r) {
    char b[32];
    // thresholds at 999.5 of the smaller unit: %.3g would print 999.7k as "1e+03k"
    if (r >= 999.5e6) std::snprintf(b, sizeof b, "%.3gG ", r / 1e9);
    else if (r >= 999.5e3) std::snprintf(b, sizeof b, "%.3gM ", r / 1e6);
    else if (r >= 999.5) std::snprintf(b, sizeof b, "%.3gk ", r / 1e3);
    else std::snprintf(b, sizeof b, "%.3g ", r);
    return b;
}
}  // namespace

ProgressMeter::ProgressMeter(std::string label, std::string unit, double total, bool enabled, double delay, std::FILE* out,
                             Clock clock)
    : label_(std::move(label)), unit_(std::move(unit)), total_(std::max(total, 1e-300)), enabled_(enabled), delay_(delay),
      out_(out), clock_(clock ? std::move(clock) : Clock(steady_seconds)), start_(clock_()) {}

ProgressMeter::~ProgressMeter() { done(); }

std::string ProgressMeter::line(double done, double elapsed) const {
    const double f = std::clamp(done / total(), 0.0, 1.0);
    char b[64];
    std::snprintf(b, sizeof b, "%3.0f%%", 100 * f);
    std::string s = label_;  // appended piecewise: GCC 12's -Wrestrict misfires on label_ + ": " + b
    s += ": ";
    s += b;
    if (elapsed > 0 && done > 0) {
        s += " " + rate_text(done / elapsed) + unit_ + "/s";
        s += ", ETA " + progress_clock_text(elapsed * (1 - f) / std::max(f, 1e-12));
    }
    return s;
}

void ProgressMeter::add(double units) {
    if (!enabled_) return;
    done_milli_.fetch_add(static_cast<std::uint64_t>(std::max(0.0, units) * 1000.0), std::memory_order_relaxed);
    maybe_draw();
}

void ProgressMeter::set_total(double total) { total_.store(std::max(total, 1e-300), std::memory_order_relaxed); }

void ProgressMeter::set_fraction(double f) {
    if (!enabled_) return;
    done_milli_.store(static_cast<std::uint64_t>(std::clamp(f, 0.0, 1.0) * total() * 1000.0), std::memory_order_relaxed);
    maybe_draw();
}

void ProgressMeter::maybe_draw() {
    std::unique_lock lock(draw_, std::try_to_lock);
    if (!lock.owns_lock()) return;  // another thread is drawing
    const double now = clock_() - start_;
    if (now < delay_ || (last_draw_ >= 0 && now - last_draw_ < 0.25)) return;
    last_draw_ = now;
    drawn_ = true;
    std::fprintf(out_, "\r\033[K%s", line(done_milli_.load(std::memory_order_relaxed) / 1000.0, now).c_str());
    std::fflush(out_);
}

void ProgressMeter::done() {
    std::lock_guard lock(draw_);
    if (drawn_) {
        std::fputs("\r\033[K", out_);
        std::fflush(out_);
    }
    drawn_ = false;
    enabled_ = false;
}

}  // namespace meshless::cli
