#include "bench/bench_common.hpp"
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include <oneapi/tbb/global_control.h>

#include "formats/atomic_file.hpp"
#include "kernels/splitmix.hpp"

namespace meshless::bench {

std::string fmt(const char* format, ...) {
    char buf[512];
    va_list ap;
    va_start(ap, format);
    const int n = std::vsnprintf(buf, sizeof buf, format, ap);
    va_end(ap);
    if (n < 0) return {};
    if (static_cast<std::size_t>(n) < sizeof buf) return std::string(buf, static_cast<std::size_t>(n));
    std::string s(static_cast<std::size_t>(n) + 1, '\0');
    va_start(ap, format);
    std::vsnprintf(s.data(), s.size(), format, ap);
    va_end(ap);
    s.resize(static_cast<std::size_t>(n));
    return s;
}

std::vector<Vec3> random_box(const Vec3& lo, const Vec3& hi, std::size_t n, std::uint64_t seed) {
    SplitMix rng{seed};
    std::vector<Vec3> p(n);
    const Vec3 e = hi - lo;
    for (auto& q : p) {
        const double x = rng.unit(), y = rng.unit(), z = rng.unit();
        q = Vec3{lo.x + x * e.x, lo.y + y * e.y, lo.z + z * e.z};
    }
    return p;
}

EvalRate eval_rate_one_thread(const Field& f, const std::vector<Vec3>& p, int reps) {
    std::vector<double> v(p.size());
    std::vector<Vec3> g(p.size());
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, 1);
    const auto thread_cpu_s = [] {
        timespec ts{};
        ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
    };
    double best = std::numeric_limits<double>::infinity(), best_cpu = best;
    for (int i = 0; i < std::max(reps, 1); ++i) {
        const double c0 = thread_cpu_s();
        Stopwatch sw;
        f.evaluate(p, v, g);
        best = std::min(best, sw.ms() / 1e3);
        best_cpu = std::min(best_cpu, thread_cpu_s() - c0);
    }
    std::size_t bad = 0;
    for (double x : v) bad += !std::isfinite(x);
    const double n = static_cast<double>(p.size());
    return {n / best, n / best_cpu, static_cast<double>(bad) / n};
}

std::pair<std::string, int> capture(const std::string& cmd) {
    std::FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return {"", -1};
    std::string text;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) text.append(buf, n);
    const int st = ::pclose(p);
    return {text, st == -1 || !WIFEXITED(st) ? -1 : WEXITSTATUS(st)};
}

std::string shell_quote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string read_file_bytes(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string bytes_str(double bytes) {
    if (bytes >= 1024.0 * 1024.0) return fmt("%.2f MiB", bytes / (1024.0 * 1024.0));
    return fmt("%.1f KiB", bytes / 1024.0);
}

// ---------------------------------------------------------------------------------------------
// Report

void Report::title(const std::string& text) {
    std::printf("%s\n%s\n", text.c_str(), std::string(text.size(), '=').c_str());
    std::fflush(stdout);
    md_ += "# " + text + "\n\n";
}

void Report::section(const std::string& text) {
    std::printf("\n%s\n%s\n", text.c_str(), std::string(text.size(), '-').c_str());
    std::fflush(stdout);
    md_ += "## " + text + "\n\n";
}

void Report::note(const std::string& text) {
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);
    md_ += text + "\n\n";
}

void Report::table(const Table& t) {
    const std::size_t nc = t.header.size();
    std::vector<std::size_t> w(nc, 0);
    auto cell = [](const std::vector<std::string>& row, std::size_t c) -> const std::string& {
        static const std::string empty;
        return c < row.size() ? row[c] : empty;
    };
    for (std::size_t c = 0; c < nc; ++c) {
        w[c] = t.header[c].size();
        for (const auto& row : t.rows) w[c] = std::max(w[c], cell(row, c).size());
    }
    auto line = [&](const std::vector<std::string>& row) {
        std::string s;
        for (std::size_t c = 0; c < nc; ++c) {
            const std::string& v = cell(row, c);
            const std::string pad(w[c] - v.size(), ' ');
            s += c == 0 ? v + pad : "  " + pad + v;
        }
        while (!s.empty() && s.back() == ' ') s.pop_back();
        return s + "\n";
    };
    std::string out = line(t.header);
    std::size_t total = 0;
    for (std::size_t c = 0; c < nc; ++c) total += w[c] + (c ? 2 : 0);
    out += std::string(total, '-') + "\n";
    for (const auto& row : t.rows) out += line(row);
    std::fputs(out.c_str(), stdout);
    std::fflush(stdout);

    auto md_line = [&](const std::vector<std::string>& row) {
        std::string s = "|";
        for (std::size_t c = 0; c < nc; ++c) {
            std::string v = cell(row, c);
            for (std::size_t p = 0; (p = v.find('|', p)) != std::string::npos; p += 2) v.replace(p, 1, "\\|");
            s += " " + v + " |";
        }
        return s + "\n";
    };
    md_ += md_line(t.header);
    md_ += "|";
    for (std::size_t c = 0; c < nc; ++c) md_ += c == 0 ? " --- |" : " ---: |";
    md_ += "\n";
    for (const auto& row : t.rows) md_ += md_line(row);
    md_ += "\n";
}

void Report::write_markdown(const std::string& path) const {
    AtomicFile f(path);
    f.write(md_);
    f.commit();
}

// ---------------------------------------------------------------------------------------------
// Machine

std::string machine_description() {
    std::ifstream in("/proc/cpuinfo");
    std::string line, model;
    int logical = 0;
    while (std::getline(in, line)) {
        if (line.rfind("processor", 0) == 0) ++logical;
        if (model.empty() && line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos) {
                model = line.substr(colon + 1);
                while (!model.empty() && model.front() == ' ') model.erase(model.begin());
            }
        }
    }
    if (model.empty()) model = "unknown CPU";
    if (logical == 0) logical = static_cast<int>(std::thread::hardware_concurrency());
    return fmt("%s, %d logical cores", model.c_str(), logical);
}

std::string now_string() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    localtime_r(&t, &tm);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M %Z", &tm);
    return buf;
}

// ---------------------------------------------------------------------------------------------
// Isovalues

std::vector<double> pick_isovalues(const Volume& v, int k) {
    std::vector<float> vals;
    vals.reserve(static_cast<std::size_t>(v.grid.voxel_count()));
    visit_samples(v.view(), [&](const auto* p) {
        const std::int64_t n = v.grid.voxel_count();
        for (std::int64_t i = 0; i < n; ++i) {
            const float x = static_cast<float>(p[i]);
            if (std::isfinite(x)) vals.push_back(x);
        }
    });
    std::vector<double> out;
    if (vals.empty() || k <= 0) return out;
    std::sort(vals.begin(), vals.end());
    const double lo = vals.front(), hi = vals.back();
    const bool integer = v.type != SampleType::f32;
    if (integer ? hi - lo < 1 : !(hi > lo)) return out;
    auto snap = [&](double q) {
        if (integer) {
            q = std::floor(q) + 0.5;
            return std::clamp(q, lo + 0.5, hi - 0.5);
        }
        // strictly inside (lo, hi)
        const double eps = (hi - lo) * 1e-6;
        return std::clamp(q, lo + eps, hi - eps);
    };
    auto present = [&](double x) {
        return std::any_of(out.begin(), out.end(), [&](double y) { return std::abs(x - y) < 1e-9 * (1 + std::abs(y)); });
    };
    for (int i = 0; i < k; ++i) {
        const std::size_t idx = static_cast<std::size_t>(
            std::llround(static_cast<double>(i + 1) / (k + 1) * static_cast<double>(vals.size() - 1)));
        const double x = snap(vals[idx]);
        if (!present(x)) out.push_back(x);
    }
    for (int m = k + 1; static_cast<int>(out.size()) < k && m <= 8 * (k + 1); m += k + 1)
        for (int j = 1; j < m && static_cast<int>(out.size()) < k; ++j) {
            const double x = snap(lo + (hi - lo) * j / m);
            if (!present(x)) out.push_back(x);
        }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<DataVolume> speed_volumes() {
    return {
        {"neghip", "neghip/neghip_64x64x64_uint8.raw", false},
        {"fuel", "fuel/fuel_64x64x64_uint8.raw", false},
        {"tooth", "tooth/tooth_103x94x161_uint8.raw", false},
        {"LIDC2 chest CT", "vtkjs_LIDC2/LIDC2.vti", true},
        {"headsq quarter", "vtk_headsq/quarter.nhdr", false},
        {"bucky", "bucky/Bucky_32x32x32_uint8.raw", false},
        {"ironProt", "vtk_ironProt/ironProt.vtk", false},
    };
}

}  // namespace meshless::bench
