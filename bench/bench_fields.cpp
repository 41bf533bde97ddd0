// meshless-bench fields: the numbers for the meshless fields of dissertation chapters 4-5
// (rbf-grid section 4.3, mpu section 5.5, global-rbf section 2.1.1):
//   1. accuracy: Franke's 3-D test function on [0,1]^3 and the Marschner-Lobb function on [-1,1]^3,
//      sampled at N uniform random points; RMS and max error against the exact function at 20,000
//      random test points in the inner 90 % of the box (away from the hull), next to SciPy's
//      RBFInterpolator (multiquadric with the same Hardy c, and thin-plate spline; neighbors=50) run
//      by bench/rbf_reference.py on the same points in the same run. Target: rbf-grid and mpu RMS
//      error <= 2x the SciPy multiquadric's.
//   2. reproduction of a linear function (max relative error <= 1e-5).
//   3. speed: construction of the Table 4.1 sets (bucky 21,114 points, fuel 2,688, neghip 16,000,
//      sampled from the real volumes; the paper: 102 s, 5 s, 50 s on a 2.8 GHz Pentium 4) on one
//      TBB thread (target >= 100x faster) and two; evaluations per second per core (value+gradient);
//      the real multiblock grids (PLOT3D comb, multicomb_*.vts) for information; 1M points:
//      construction time, FieldBuildStats::memory_bytes and peak resident memory (VmHWM, reset
//      through /proc/self/clear_refs before each build).
// All random sets come from one splitmix64 generator with fixed seeds (the same in every run).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <thread>

#include "bench/bench_common.hpp"
#include "formats/atomic_file.hpp"
#include "formats/json.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/errors.hpp"
#include "kernels/splitmix.hpp"
#include "kernels/make_field.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/multiquadric_sum.hpp"
#include "kernels/trilinear_field.hpp"

namespace meshless::bench {

namespace {

namespace fs = std::filesystem;

constexpr double kAccuracyTarget = 2.0;    // local field RMS error <= 2x SciPy's (same points)
constexpr double kLinearTarget = 1e-5;     // linear reproduction, max relative error
constexpr double kSpeedupTarget = 100.0;   // construction >= 100x the paper's Pentium 4 time, one core
constexpr std::size_t kTestPoints = 20000;
constexpr std::size_t kEvalBatch = 100000;
constexpr double kEvalTargetM = 4.0;      // value + gradient >= 4 M points/s per core (rbf-grid, mpu)
constexpr double kBuild1MTarget = 2.0;    // construction of 1M points <= 2 s on 2 threads
constexpr int kScipyNeighbors = 50;
constexpr double kScipyBudgetS = 60.0;     // skip a SciPy run estimated to take longer
constexpr std::uint32_t kGlobalMax = 4000; // global-rbf only for N <= this
constexpr double kMiB = 1024.0 * 1024.0;

// ---- random numbers, test functions -----------------------------------------------------------



/// Franke's 3-D test function on [0,1]^3.
double franke3(const Vec3& p) {
    const double x = 9 * p.x, y = 9 * p.y, z = 9 * p.z;
    auto sq = [](double v) { return v * v; };
    return 0.75 * std::exp(-(sq(x - 2) + sq(y - 2) + sq(z - 2)) / 4) +
           0.75 * std::exp(-sq(x + 1) / 49 - (y + 1) / 10 - (z + 1) / 10) +
           0.5 * std::exp(-(sq(x - 7) + sq(y - 3) + sq(z - 5)) / 4) -
           0.2 * std::exp(-sq(x - 4) - sq(y - 7) - sq(z - 5));
}

struct TestFunction {
    std::string name;
    std::function<double(const Vec3&)> f;
    Vec3 lo, hi;  ///< sampling box; test points in its inner 90 %
};

std::vector<TestFunction> accuracy_functions() {
    return {
        {"Franke 3-D", franke3, {0, 0, 0}, {1, 1, 1}},
        {"Marschner-Lobb",
         [](const Vec3& p) { return analytic_value(AnalyticField::marschner_lobb, p); },
         {-1, -1, -1},
         {1, 1, 1}},
    };
}

PointSet make_points(const std::vector<Vec3>& pos, const std::function<double(const Vec3&)>& f,
                     const std::string& name) {
    PointSet ps;
    ps.pos = pos;
    ps.value.resize(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) ps.value[i] = f(pos[i]);
    ps.value_name = name;
    ps.blocks = {PointSetBlock{"random", {static_cast<std::int64_t>(pos.size()), 1, 1}, 0, pos.size()}};
    return ps;
}

struct Err {
    double rms = 0, max = 0;
    std::size_t nonfinite = 0;
};

Err errors(const std::vector<double>& got, const std::vector<double>& exact) {
    Err e;
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        if (!std::isfinite(got[i])) {
            ++e.nonfinite;
            continue;
        }
        const double d = std::abs(got[i] - exact[i]);
        sum += d * d;
        e.max = std::max(e.max, d);
        ++n;
    }
    e.rms = n ? std::sqrt(sum / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
    return e;
}

std::string count_str(std::size_t n) {
    if (n >= 1000000 && n % 1000000 == 0) return fmt("%zuM", n / 1000000);
    if (n >= 1000 && n % 1000 == 0) return fmt("%zuK", n / 1000);
    return fmt("%zu", n);
}

std::string sci(double v) { return std::isfinite(v) ? fmt("%.3g", v) : "-"; }

FieldParams params_for(FieldKind k, const BenchOptions& o) {
    FieldParams p;
    p.kind = k;
    if (o.hardy_c_spacing >= 0) p.hardy_c_spacing = o.hardy_c_spacing;
    return p;
}

// ---- memory -----------------------------------------------------------------------------------

/// A field of /proc/self/status in bytes ("VmRSS", "VmHWM"); 0 when unknown.
double proc_status_bytes(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    const std::string k = std::string(key) + ":";
    while (std::getline(in, line))
        if (line.rfind(k, 0) == 0) return std::strtod(line.c_str() + k.size(), nullptr) * 1024.0;
    return 0;
}

/// Resets the peak-RSS high-water mark to the current RSS (Linux >= 4.0); false when refused.
bool reset_peak_rss() {
    std::ofstream f("/proc/self/clear_refs");
    if (!f) return false;
    f << "5";
    f.flush();
    return static_cast<bool>(f);
}

double rusage_maxrss_bytes() {
    rusage ru{};
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0;
    return static_cast<double>(ru.ru_maxrss) * 1024.0;
}

// ---- SciPy reference --------------------------------------------------------------------------

/// A folder under the system temp folder, removed with its contents by the destructor.
struct FieldsScratch {
    fs::path path;
    FieldsScratch() {
        path = fs::temp_directory_path() / ("meshless-bench-fields-" + std::to_string(::getpid()));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~FieldsScratch() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    FieldsScratch(const FieldsScratch&) = delete;
    FieldsScratch& operator=(const FieldsScratch&) = delete;
};

struct RefConfig {
    std::string label;  ///< row label
    std::string kernel;
    int degree = 1;
    bool hardy = false;  ///< epsilon = 1/c_world
};

const std::vector<RefConfig>& ref_configs() {
    static const std::vector<RefConfig> c = {
        {fmt("scipy MQ k=%d", kScipyNeighbors), "multiquadric", 1, true},
        {fmt("scipy TPS k=%d", kScipyNeighbors), "thin_plate_spline", 1, false},
    };
    return c;
}

struct RefRun {
    std::vector<std::vector<double>> pred;  ///< per config, per test point
    std::vector<double> fit_s, eval_s;
    double wall_s = 0;
};

class Scipy {
public:
    Scipy(const BenchOptions& o, const FieldsScratch& scratch) : scratch_(scratch) {
        script_ = (fs::path(o.bench_dir) / "rbf_reference.py").string();
        python_ = o.python;
        if (!fs::exists(script_)) {
            why_ = "rbf_reference.py not found in '" + o.bench_dir + "' (give --bench-dir): SciPy reference skipped";
            return;
        }
        const auto [text, code] = capture(shell_quote(python_) + " " + shell_quote(script_) + " --check 2>/dev/null");
        if (code != 0) {
            why_ = "SciPy not installed (apt-get install python3-scipy): reference skipped";
            return;
        }
        try {
            const Json j = parse_json(text, script_ + " --check");
            if (const Json* v = j.find("scipy"); v && v->is_string()) version_ = v->str;
            ok_ = true;
        } catch (const std::exception& e) {
            why_ = std::string("rbf_reference.py --check: unreadable output: ") + e.what();
        }
    }
    bool ok() const { return ok_; }
    const std::string& why() const { return why_; }
    const std::string& version() const { return version_; }

    /// Fits each reference config to ps and evaluates it at tests; nullopt (reason in err) on failure.
    std::optional<RefRun> run(const PointSet& ps, const std::vector<Vec3>& tests, double c_world, std::string& err) const {
        const fs::path pts = scratch_.path / "points.bin", tst = scratch_.path / "tests.bin",
                       out = scratch_.path / "pred";
        write_records(pts, ps.pos, &ps.value);
        write_records(tst, tests, nullptr);
        std::string cmd = shell_quote(python_) + " " + shell_quote(script_) + " --points " + shell_quote(pts.string()) + " --tests " +
                          shell_quote(tst.string()) + " --out " + shell_quote(out.string()) + fmt(" --neighbors %d", kScipyNeighbors);
        for (const RefConfig& c : ref_configs())
            cmd += fmt(" --config %s:%.17g:%d", c.kernel.c_str(), c.hardy ? 1.0 / c_world : 1.0, c.degree);
        cmd += " 2>" + shell_quote((scratch_.path / "stderr.txt").string());
        Stopwatch sw;
        const auto [text, code] = capture(cmd);
        RefRun rr;
        rr.wall_s = sw.ms() / 1e3;
        if (code != 0) {
            std::ifstream in(scratch_.path / "stderr.txt");
            std::string line, last;
            while (std::getline(in, line))
                if (!line.empty()) last = line;
            err = fmt("rbf_reference.py failed (exit status %d): %s", code, last.c_str());
            return std::nullopt;
        }
        try {
            const Json j = parse_json(text, script_ + " output");
            const Json* cs = j.find("configs");
            if (!cs || !cs->is_array() || cs->arr.size() != ref_configs().size())
                throw std::runtime_error("missing configs");
            for (std::size_t i = 0; i < cs->arr.size(); ++i) {
                const Json* f = cs->arr[i].find("fit_seconds");
                const Json* e = cs->arr[i].find("eval_seconds");
                rr.fit_s.push_back(f && f->is_number() ? f->num : 0);
                rr.eval_s.push_back(e && e->is_number() ? e->num : 0);
                const fs::path pf = out.string() + "." + std::to_string(i);
                std::ifstream in(pf, std::ios::binary);
                std::vector<double> v(tests.size());
                in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(double)));
                if (in.gcount() != static_cast<std::streamsize>(v.size() * sizeof(double)))
                    throw std::runtime_error("short prediction file " + pf.string());
                rr.pred.push_back(std::move(v));
            }
        } catch (const std::exception& e) {
            err = std::string("rbf_reference.py: unreadable output: ") + e.what();
            return std::nullopt;
        }
        return rr;
    }

private:
    /// int64 n, then n records of float64 x, y, z (, value) in host order (little-endian on x86).
    static void write_records(const fs::path& path, const std::vector<Vec3>& pos, const std::vector<double>* val) {
        const std::size_t cols = val ? 4 : 3;
        std::vector<double> buf;
        buf.reserve(pos.size() * cols);
        for (std::size_t i = 0; i < pos.size(); ++i) {
            buf.insert(buf.end(), {pos[i].x, pos[i].y, pos[i].z});
            if (val) buf.push_back((*val)[i]);
        }
        const std::int64_t n = static_cast<std::int64_t>(pos.size());
        AtomicFile f(path.string());
        f.write(&n, sizeof n);
        f.write(buf.data(), buf.size() * sizeof(double));
        f.commit();
    }

    const FieldsScratch& scratch_;
    std::string script_, python_, why_, version_;
    bool ok_ = false;
};

// ---- 1. accuracy ------------------------------------------------------------------------------

void run_field_accuracy(const BenchOptions& o, const Scipy& scipy, Report& r) {
    r.section("Fields: accuracy on scattered samples (Franke 3-D, Marschner-Lobb) vs SciPy RBFInterpolator");
    const std::vector<std::size_t> counts =
        o.quick ? std::vector<std::size_t>{1000, 10000} : std::vector<std::size_t>{1000, 10000, 100000, 1000000};
    const FieldParams defaults;
    r.note(fmt("N uniform random points in the sampling box (Franke: [0,1]^3; Marschner-Lobb, f_M = 6, alpha = 0.25: "
               "[-1,1]^3), values exact. Errors against the exact function at %zu random test points in the inner 90%% "
               "of the box ([0.05,0.95]^3 and [-0.9,0.9]^3: the fields and SciPy extrapolate near the hull, which "
               "is left out). Default parameters: Hardy c = %.3g x bounding-box diagonal (c_world ~ %.4g for Franke, "
               "%.4g for M-L), binning m = %g, MPU N = %u, min points %u, alpha = %g, blend alpha %g; global-rbf only for N <= %u. "
               "SciPy: RBFInterpolator(neighbors=%d) on the same points: 'multiquadric' with epsilon = 1/c_world "
               "and degree 1 (the same Hardy multiquadric + linear polynomial), and 'thin_plate_spline' (degree 1). "
               "ratio = our RMS error / SciPy multiquadric's RMS error; target <= %.0f for rbf-grid and mpu. "
               "build s: construction (all threads; SciPy: the RBFInterpolator constructor, which with neighbors only "
               "builds a k-d tree: its local solves happen at evaluation), eval s: the %zu test points (ours: one "
               "thread; SciPy: NumPy/LAPACK threads, the Python loop over neighbourhoods). "
               "Errors are absolute (the value ranges at the test points follow the table).",
               kTestPoints, defaults.hardy_c_rel, defaults.hardy_c_rel * std::sqrt(3.0),
               defaults.hardy_c_rel * 2 * std::sqrt(3.0), defaults.binning_m, defaults.mpu_max_points,
               defaults.mpu_min_points, defaults.mpu_alpha, defaults.mpu_blend_alpha, kGlobalMax, kScipyNeighbors, kAccuracyTarget, kTestPoints));
    if (scipy.ok()) r.note("SciPy " + scipy.version() + " (" + o.python + ").");
    else r.note(scipy.why());

    Table t;
    t.header = {"function", "N", "field", "build s", "eval s", "RMS err", "max err", "ratio RMS", "ratio max", "target"};
    std::vector<std::string> notes;
    int pass = 0, fail = 0;
    std::uint64_t fn_seed = 1000;
    for (const TestFunction& fn : accuracy_functions()) {
        ++fn_seed;
        const Vec3 m = (fn.hi - fn.lo) * 0.05;
        const std::vector<Vec3> tests = random_box(fn.lo + m, fn.hi - m, kTestPoints, fn_seed * 7919);
        std::vector<double> exact(tests.size());
        for (std::size_t i = 0; i < tests.size(); ++i) exact[i] = fn.f(tests[i]);
        const auto [elo, ehi] = std::minmax_element(exact.begin(), exact.end());
        notes.push_back(fmt("%s: exact values at the test points in [%.3g, %.3g].", fn.name.c_str(), *elo, *ehi));
        double last_ref_s = 0;
        std::size_t last_ref_n = 0;
        for (std::size_t n : counts) {
            std::fprintf(stderr, "bench fields: accuracy %s N=%zu...\n", fn.name.c_str(), n);
            const PointSet ps = make_points(random_box(fn.lo, fn.hi, n, fn_seed * 1000003 + n), fn.f, "f");
            std::optional<Err> ref;
            // SciPy first: its multiquadric error is the denominator of the ratios
            std::vector<std::vector<std::string>> ref_rows;
            if (scipy.ok()) {
                const double est = last_ref_n ? last_ref_s * static_cast<double>(n) / static_cast<double>(last_ref_n) : 0;
                if (est > kScipyBudgetS) {
                    notes.push_back(fmt("%s N=%s: SciPy skipped (estimated %.0f s from N=%s's %.1f s, > %.0f s).",
                                        fn.name.c_str(), count_str(n).c_str(), est, count_str(last_ref_n).c_str(),
                                        last_ref_s, kScipyBudgetS));
                } else {
                    std::string err;
                    const double c = hardy_c_world_for(defaults, ps.bounds());
                    if (auto rr = scipy.run(ps, tests, c, err)) {
                        last_ref_s = rr->wall_s;
                        last_ref_n = n;
                        for (std::size_t k = 0; k < rr->pred.size(); ++k) {
                            const Err e = errors(rr->pred[k], exact);
                            if (k == 0) ref = e;
                            ref_rows.push_back({fn.name, count_str(n), ref_configs()[k].label, fmt("%.2f", rr->fit_s[k]),
                                                fmt("%.2f", rr->eval_s[k]), sci(e.rms), sci(e.max),
                                                ref ? fmt("%.2f", e.rms / ref->rms) : "-",
                                                ref ? fmt("%.2f", e.max / ref->max) : "-", k == 0 ? "(ref)" : ""});
                        }
                    } else {
                        notes.push_back(fn.name + " N=" + count_str(n) + ": " + err);
                    }
                }
            }
            for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu, FieldKind::global_rbf}) {
                if (k == FieldKind::global_rbf && n > kGlobalMax) continue;
                FieldBuildStats st;
                std::unique_ptr<Field> f;
                try {
                    f = make_field(ps, params_for(k, o), &st);
                } catch (const std::exception& e) {
                    notes.push_back(fmt("%s N=%s %s: build failed: %s", fn.name.c_str(), count_str(n).c_str(),
                                        std::string(field_kind_name(k)).c_str(), e.what()));
                    continue;
                }
                std::vector<double> got(tests.size());
                Stopwatch sw;
                f->evaluate(tests, got, {});
                const double eval_s = sw.ms() / 1e3;
                const Err e = errors(got, exact);
                std::string target;
                const bool local = k != FieldKind::global_rbf;
                if (ref && ref->rms > 0) {
                    const double q = e.rms / ref->rms;
                    if (local) {
                        const bool ok = q <= kAccuracyTarget && e.nonfinite == 0;
                        target = ok ? "PASS" : "FAIL";
                        (ok ? pass : fail)++;
                    } else {
                        target = "(info)";
                    }
                }
                if (e.nonfinite) target += fmt(" %zu NaN", e.nonfinite);
                t.add({fn.name, count_str(n), std::string(field_kind_name(k)), fmt("%.2f", st.build_seconds),
                       fmt("%.2f", eval_s), sci(e.rms), sci(e.max), ref ? fmt("%.2f", e.rms / ref->rms) : "-",
                       ref ? fmt("%.2f", e.max / ref->max) : "-", target});
            }
            for (auto& row : ref_rows) t.add(std::move(row));
        }
    }
    r.table(t);
    for (const std::string& s : notes) r.note(s);
    if (pass + fail) r.note(fmt("Accuracy target (RMS error within %.0fx SciPy's at equal N): %d PASS, %d FAIL.",
                                kAccuracyTarget, pass, fail));
}

// ---- 2. linear reproduction -------------------------------------------------------------------

void run_field_reproduction(const BenchOptions& o, Report& r) {
    r.section("Fields: reproduction of a linear function");
    const std::vector<std::size_t> counts =
        o.quick ? std::vector<std::size_t>{1000, 10000} : std::vector<std::size_t>{1000, 10000, 100000};
    auto lin = [](const Vec3& p) { return 1.0 + 2.0 * p.x - 3.0 * p.y + 0.5 * p.z; };
    r.note(fmt("f(x,y,z) = 1 + 2x - 3y + 0.5z sampled at N uniform random points in [0,1]^3; max relative error = "
               "max |F - f| / max |f| over %zu random points of the WHOLE box [0,1]^3 (hull included), and at the "
               "data points. Target <= %.0e.",
               kTestPoints, kLinearTarget));
    const std::vector<Vec3> tests = random_box({0, 0, 0}, {1, 1, 1}, kTestPoints, 4242);
    std::vector<double> exact(tests.size());
    double fmax = 0;
    for (std::size_t i = 0; i < tests.size(); ++i) {
        exact[i] = lin(tests[i]);
        fmax = std::max(fmax, std::abs(exact[i]));
    }
    Table t;
    t.header = {"N", "field", "max rel err (box)", "max rel err (data)", "NaN", "target"};
    for (std::size_t n : counts) {
        const PointSet ps = make_points(random_box({0, 0, 0}, {1, 1, 1}, n, 77 + n), lin, "linear");
        double dmax = 0;
        for (double v : ps.value) dmax = std::max(dmax, std::abs(v));
        for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu, FieldKind::global_rbf}) {
            if (k == FieldKind::global_rbf && n > kGlobalMax) continue;
            std::fprintf(stderr, "bench fields: linear %s N=%zu...\n", std::string(field_kind_name(k)).c_str(), n);
            std::unique_ptr<Field> f;
            try {
                f = make_field(ps, params_for(k, o));
            } catch (const std::exception& e) {
                t.add({count_str(n), std::string(field_kind_name(k)), "-", "-", "-", std::string("FAIL ") + e.what()});
                continue;
            }
            std::vector<double> got(tests.size());
            f->evaluate(tests, got, {});
            const Err e = errors(got, exact);
            std::vector<double> at(ps.size());
            f->evaluate(ps.pos, at, {});
            const Err ed = errors(at, ps.value);
            const double rb = e.max / fmax, rd = ed.max / dmax;
            const bool ok = rb <= kLinearTarget && rd <= kLinearTarget && e.nonfinite == 0 && ed.nonfinite == 0;
            t.add({count_str(n), std::string(field_kind_name(k)), fmt("%.2e", rb), fmt("%.2e", rd),
                   fmt("%zu", e.nonfinite + ed.nonfinite), ok ? "PASS" : "FAIL"});
        }
    }
    r.table(t);
}

// ---- 3. speed ---------------------------------------------------------------------------------

struct SpeedSet {
    std::string label;
    std::string source;
    PointSet ps;
    double paper_s = 0;  ///< Table 4.1 (2.8 GHz Pentium 4); 0 = no paper time
};

/// n uniform random positions in the volume's bounds with trilinear values (as `meshless sample`).
PointSet sample_volume(const Volume& v, std::size_t n, std::uint64_t seed) {
    const TrilinearField field(v.view());
    const GridSpec& g = v.grid;
    Vec3 lo{g.origin[0], g.origin[1], g.origin[2]};
    Vec3 ext{static_cast<double>(g.dims[0] - 1) * g.spacing[0], static_cast<double>(g.dims[1] - 1) * g.spacing[1],
             static_cast<double>(g.dims[2] - 1) * g.spacing[2]};
    SplitMix rng{seed};
    PointSet ps;
    ps.value_name = "value";
    std::vector<Vec3> p(4096);
    std::vector<double> val(p.size());
    std::size_t draws = 0;
    while (ps.pos.size() < n && draws < 20 * n + 1000) {
        for (auto& q : p) q = Vec3{lo.x + rng.unit() * ext.x, lo.y + rng.unit() * ext.y, lo.z + rng.unit() * ext.z};
        draws += p.size();
        field.evaluate(p, val, {});
        for (std::size_t i = 0; i < p.size() && ps.pos.size() < n; ++i)
            if (std::isfinite(val[i])) {
                ps.pos.push_back(p[i]);
                ps.value.push_back(val[i]);
            }
    }
    ps.blocks = {PointSetBlock{"sample", {static_cast<std::int64_t>(ps.pos.size()), 1, 1}, 0, ps.pos.size()}};
    return ps;
}

std::vector<SpeedSet> table41_sets(const BenchOptions& o, Report& r) {
    struct Spec {
        std::string label, rel;
        std::size_t n;
        double paper_s;
    };
    const std::vector<Spec> specs = {
        {"bucky ball", "bucky/Bucky_32x32x32_uint8.raw", 21114, 102},
        {"fuel injection", "fuel/fuel_64x64x64_uint8.raw", 2688, 5},
        {"neghip", "neghip/neghip_64x64x64_uint8.raw", 16000, 50},
    };
    std::vector<SpeedSet> out;
    std::error_code ec;
    std::string missing;
    std::uint64_t seed = 41;
    for (const Spec& s : specs) {
        ++seed;
        const fs::path path = fs::path(o.data_dir) / s.rel;
        try {
            if (!fs::exists(path, ec)) throw IoError(path.string() + ": not found");
            const Volume v = read_volume(path.string());
            out.push_back({s.label, s.rel, sample_volume(v, s.n, seed), s.paper_s});
        } catch (const std::exception& e) {
            missing += (missing.empty() ? "" : "; ") + std::string(e.what());
            // same count from Franke's function so the row is still measured
            out.push_back({s.label + " (Franke stand-in)", "Franke 3-D",
                           make_points(random_box({0, 0, 0}, {1, 1, 1}, s.n, seed), franke3, "f"), s.paper_s});
        }
    }
    if (!missing.empty()) r.note("not found or unreadable: " + missing + " (Franke's function sampled instead)");
    return out;
}

std::vector<SpeedSet> multiblock_sets(const BenchOptions& o, Report& r) {
    std::vector<SpeedSet> out;
    const fs::path dir = fs::path(o.data_dir) / "plot3d";
    try {
        out.push_back({"PLOT3D comb (density)", "plot3d/combxyz.bin + combq.bin", read_point_set((dir / "combxyz.bin").string()), 0});
    } catch (const std::exception& e) {
        r.note(std::string("PLOT3D comb skipped: ") + e.what());
    }
    try {
        std::vector<std::string> paths;
        for (int i = 0; i < 3; ++i) paths.push_back((dir / fmt("multicomb_%d.vts", i)).string());
        out.push_back({"multicomb_0..2.vts", "plot3d/multicomb_*.vts", read_point_set(paths), 0});
    } catch (const std::exception& e) {
        r.note(std::string("multicomb_*.vts skipped: ") + e.what());
    }
    return out;
}

/// Best build time over reps on `threads` TBB threads (0 = default), with the stats of the last.
double best_build(const BenchOptions& o, const PointSet& ps, FieldKind k, int threads, int reps, FieldBuildStats& st) {
    std::optional<oneapi::tbb::global_control> limit;
    if (threads > 0)
        limit.emplace(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < reps; ++i) {
        Stopwatch sw;
        auto f = make_field(ps, params_for(k, o), &st);
        best = std::min(best, sw.ms() / 1e3);
    }
    return best;
}

/// Value+gradient evaluations per second on one thread: a batch of kEvalBatch random points inside
/// the field's bounds, best of reps. Also the fraction of non-finite values.
std::pair<double, double> eval_rate(const Field& f, int reps, std::uint64_t seed) {
    const auto b = f.bounds();
    const EvalRate e = eval_rate_one_thread(f, random_box(b[0], b[1], kEvalBatch, seed), reps);
    return {e.per_s, e.nan_share};
}

/// Nanoseconds per multiquadric term (value + gradient) of the sum kernel alone, its data in
/// cache: 5 locals of 71 centres (an mpu query's shape) summed at 20000 points, one thread, best
/// of 5. The evaluation ceiling of a field = 1 / (terms per query x this).
double sum_kernel_ns_per_term() {
    constexpr std::size_t kLocals = 5, kCentres = 71, kQueries = 20000;
    const std::vector<Vec3> c = random_box({0, 0, 0}, {1, 1, 1}, kLocals * kCentres, 4711);
    std::vector<double> px(c.size()), py(c.size()), pz(c.size()), lambda(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) {
        px[i] = c[i].x;
        py[i] = c[i].y;
        pz[i] = c[i].z;
        lambda[i] = 1.0 / static_cast<double>(i + 1);
    }
    std::vector<MqRun> runs(kLocals);
    std::vector<MqLocalTerms> locals(kLocals);
    for (std::size_t l = 0; l < kLocals; ++l) {
        runs[l] = MqRun{static_cast<std::uint32_t>(l * kCentres), static_cast<std::uint32_t>(kCentres)};
        locals[l] = MqLocalTerms{&runs[l], 1, lambda.data() + l * kCentres, 0.0025};
    }
    const std::vector<Vec3> q = random_box({0, 0, 0}, {1, 1, 1}, kQueries, 4712);
    std::vector<MqSum> out(kLocals);
    double best = std::numeric_limits<double>::infinity(), sink = 0;
    for (int rep = 0; rep < 5; ++rep) {
        Stopwatch sw;
        for (const Vec3& x : q) {
            multiquadric_sums(px.data(), py.data(), pz.data(), locals, x, true, out.data());
            sink += out[0].v;
        }
        best = std::min(best, sw.ms() * 1e6);
    }
    if (!std::isfinite(sink)) std::fprintf(stderr, "bench fields: sum kernel gave %g\n", sink);
    return best / static_cast<double>(kQueries * kLocals * kCentres);
}

/// The mean number of multiquadric terms an mpu query sums at the evaluation-rate points (0 for
/// the other fields, which do not say).
double mean_terms_per_query(const Field& f, std::uint64_t seed) {
    const auto* m = dynamic_cast<const MpuField*>(&f);
    if (m == nullptr) return 0;
    const auto b = f.bounds();
    const std::vector<Vec3> p = random_box(b[0], b[1], kEvalBatch, seed);
    double terms = 0;
    for (const Vec3& x : p) terms += static_cast<double>(m->terms_at(x));
    return terms / static_cast<double>(p.size());
}

void run_field_speed(const BenchOptions& o, Report& r) {
    r.section("Fields: construction speed (Table 4.1) and evaluation rate");
    const int reps = o.quick ? 1 : 3;
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    r.note(fmt("Table 4.1's multiblock sets at their point counts, made from the real volumes: uniform random "
               "positions in the volume's bounds (voxel units), values by trilinear interpolation, fixed seeds "
               "(as `meshless sample`). Paper: 2.8 GHz Pentium 4, one core. Construction = make_field (merge, "
               "binning/octree, every local solve), best of %d, on 1 TBB thread (tbb::global_control) and on 2; "
               "speedup = paper time / our 1-thread time (target >= %.0fx). eval Mpts/s: value + gradient of %zu "
               "random points inside the bounds, one thread, best of %d (NaN %%: points outside every support; eval target, "
               ">= %.0f M points/s per core for rbf-grid and mpu). "
               "This machine has %u logical cores.",
               reps, kSpeedupTarget, kEvalBatch, reps, kEvalTargetM, hw));
    std::vector<SpeedSet> sets = table41_sets(o, r);
    if (!o.quick)
        for (auto& s : multiblock_sets(o, r)) sets.push_back(std::move(s));
    Table t;
    t.header = {"set", "points", "field", "paper s", "1 thread s", "speedup", "target", "2 threads s", "2T speedup",
                "locals", "memory", "eval Mpts/s (1 core)", "eval target", "NaN %", "terms/query", "sums-alone Mpts/s"};
    const double ns_term = sum_kernel_ns_per_term();
    std::uint64_t seed = 900;
    for (const SpeedSet& s : sets) {
        for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu, FieldKind::global_rbf}) {
            if (k == FieldKind::global_rbf && s.ps.size() > kGlobalMax) continue;
            std::fprintf(stderr, "bench fields: speed %s %s...\n", s.label.c_str(), std::string(field_kind_name(k)).c_str());
            FieldBuildStats st1, st2;
            double t1 = 0, t2 = 0;
            std::unique_ptr<Field> f;
            try {
                t1 = best_build(o, s.ps, k, 1, reps, st1);
                t2 = best_build(o, s.ps, k, 2, reps, st2);
                f = make_field(s.ps, params_for(k, o));
            } catch (const std::exception& e) {
                r.note(fmt("%s %s: build failed: %s", s.label.c_str(), std::string(field_kind_name(k)).c_str(), e.what()));
                continue;
            }
            const auto [rate, nan] = eval_rate(*f, reps, ++seed);
            const double terms = mean_terms_per_query(*f, seed);
            std::string speedup = "-", target = "(info)";
            if (s.paper_s > 0) {
                const double q = s.paper_s / t1;
                speedup = fmt("%.0fx", q);
                target = k == FieldKind::global_rbf ? "(info)" : q >= kSpeedupTarget ? "PASS" : "FAIL";
            }
            t.add({s.label, fmt("%zu", s.ps.size()), std::string(field_kind_name(k)),
                   s.paper_s > 0 ? fmt("%.0f", s.paper_s) : "-", fmt("%.3f", t1), speedup, target, fmt("%.3f", t2),
                   fmt("%.2f", t1 / t2), fmt("%llu", static_cast<unsigned long long>(st1.locals)),
                   bytes_str(static_cast<double>(st1.memory_bytes)), fmt("%.2f", rate / 1e6),
                   k == FieldKind::global_rbf ? std::string("(info)") : rate / 1e6 >= kEvalTargetM ? "PASS" : "FAIL",
                   fmt("%.2f", 100 * nan), terms > 0 ? fmt("%.0f", terms) : std::string("-"),
                   terms > 0 ? fmt("%.2f", 1e3 / (terms * ns_term)) : std::string("-")});
        }
    }
    r.table(t);
    r.note("memory: FieldBuildStats::memory_bytes (heap held by the field after construction). locals: local "
           "interpolants (RBF-grid cells with a centre, MPU leaves; 1 for global-rbf).");
    r.note(fmt("Evaluation ceiling, measured in this run: the multiquadric sum kernel alone (%s, value + gradient, data in "
               "cache, 5 locals x 71 centres per query) costs %.3f ns per term. terms/query: the centres an mpu query sums "
               "(MpuField::terms_at, mean over the evaluation points); sums-alone Mpts/s = 1000 / (terms/query x ns per "
               "term), the rate the field would reach if selecting, blending and the memory traffic of the locals cost "
               "nothing: where it is below the %.0f M points/s target, the target needs fewer terms per query.",
               multiquadric_sum_isa(), ns_term, kEvalTargetM));
}

// ---- 4. one million points --------------------------------------------------------------------

void run_field_million(const BenchOptions& o, Report& r) {
    r.section("Fields: one million points (construction, memory, evaluation)");
    const std::size_t n = 1000000;
    const bool can_reset = reset_peak_rss();
    r.note(fmt("Franke 3-D at 1M uniform random points in [0,1]^3, construction on 2 TBB threads (tbb::global_control, "
               "as --threads 2; target: <= %.0f s), evaluation on one (target >= %.0f M points/s per core). RSS before: resident memory before "
               "the build (the point set, 32 MB, included); peak RSS: VmHWM of /proc/self/status after %s, i.e. the "
               "high-water mark of construction and of evaluating %zu points (value + gradient, one thread); "
               "getrusage's ru_maxrss agrees with it after the reset. Bound stated: the field's peak over the RSS "
               "before <= 1 KiB per point (1 GiB at 1M), memory_bytes <= 512 B per point.",
               kBuild1MTarget, kEvalTargetM, can_reset ? "resetting it (echo 5 > /proc/self/clear_refs) before each build"
                         : "no reset (clear_refs refused: the peak is the process's, whole run)",
               kEvalBatch));
    const PointSet ps = make_points(random_box({0, 0, 0}, {1, 1, 1}, n, 31337), franke3, "f");
    Table t;
    t.header = {"field", "points", "build s (2 threads)", "memory_bytes", "B/point", "RSS before", "peak RSS", "peak - before",
                "ru_maxrss", "eval Mpts/s (1 core)", "bound", "targets"};
    for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu}) {
        std::fprintf(stderr, "bench fields: 1M %s...\n", std::string(field_kind_name(k)).c_str());
        if (can_reset) reset_peak_rss();
        const double before = proc_status_bytes("VmRSS");
        FieldBuildStats st;
        std::unique_ptr<Field> f;
        try {
            oneapi::tbb::global_control two(oneapi::tbb::global_control::max_allowed_parallelism, 2);
            f = make_field(ps, params_for(k, o), &st);
        } catch (const std::exception& e) {
            r.note(fmt("%s: build failed: %s", std::string(field_kind_name(k)).c_str(), e.what()));
            continue;
        }
        const auto [rate, nan] = eval_rate(*f, 1, 555);
        (void)nan;
        const double peak = proc_status_bytes("VmHWM"), maxrss = rusage_maxrss_bytes();
        const double per = static_cast<double>(st.memory_bytes) / static_cast<double>(n);
        const bool ok = peak - before <= 1024.0 * static_cast<double>(n) && per <= 512;
        t.add({std::string(field_kind_name(k)), "1M", fmt("%.2f", st.build_seconds), bytes_str(static_cast<double>(st.memory_bytes)),
               fmt("%.0f", per), fmt("%.0f MiB", before / kMiB), fmt("%.0f MiB", peak / kMiB),
               fmt("%.0f MiB", (peak - before) / kMiB), fmt("%.0f MiB", maxrss / kMiB), fmt("%.2f", rate / 1e6),
               ok ? "PASS" : "FAIL",
               fmt("build %s, eval %s", st.build_seconds <= kBuild1MTarget ? "PASS" : "FAIL",
                   rate / 1e6 >= kEvalTargetM ? "PASS" : "FAIL")});
        f.reset();
    }
    r.table(t);
}

}  // namespace

void run_fields(const BenchOptions& o, Report& r) {
    const FieldsScratch scratch;
    const Scipy scipy(o, scratch);
    run_field_accuracy(o, scipy, r);
    run_field_reproduction(o, r);
    run_field_speed(o, r);
    if (o.quick) r.note("--quick: the 1M-point construction and memory table is skipped; N = 1K and 10K only; "
                        "no PLOT3D/VTS multiblock rows.");
    else run_field_million(o, r);
}

}  // namespace meshless::bench
