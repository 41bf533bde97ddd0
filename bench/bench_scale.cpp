// `meshless-bench scale`: the scattered-data isosurface (dissertation chapter 5) as the point count
// grows, in memory and out of core, against the VTK peer a user reaches for at these sizes; every
// row a whole process run as users run it (docs/architecture.md, "Fields out of core").
// Per size N (--sizes, default 10^5, 10^6, 3x10^6; --quick 2x10^4):
//   1. `meshless sample LIDC2.vti --count N --seed 5` (the chest CT of the data folder: sharp edges),
//      cached in the work folder (--work) or a temporary one;
//   2. `meshless isosurface SET.ply --iso 100.5 -o a.ply`: the field in memory whole;
//   3. `meshless convert SET.ply -o SET.mlc` (Morton point store), then `isosurface SET.mlc` without a
//      budget (one slab) and with `--memory M`, M = two thirds of the one-slab run's peak RSS: time, peak RSS,
//      slabs and fits copied (its --stats), and whether its bytes equal the one-slab run's;
//   4. the peer (bench/scattered_peers.py --method interp): vtkPointInterpolator, Gaussian kernel on
//      the 8 closest points, onto a grid with about as many nodes as points, then vtkFlyingEdges3D.
// Ratios: time per point against the smallest size (linearity), the slab run against the one-slab
// run, and the in-memory run against the peer. Peak RSS: the command's own (run_sh's wrapper).
// A second table builds the mpu and rbf-grid fields of each set in this process (make_field, all
// threads: wall and CPU seconds) and times their evaluation (value + gradient, one thread) at random
// points in the bounds and at the nodes of a regular grid over them, against the targets.
#include <sys/resource.h>
#include <sys/types.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/bench_common.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/make_field.hpp"
#include "kernels/mpu_field.hpp"

namespace meshless::bench {

namespace {

namespace fs = std::filesystem;

constexpr double kLimit = 3600;  // seconds a command may take
constexpr double kMiB = 1024.0 * 1024.0;
constexpr std::size_t kEvalPoints = 100000;  // evaluation batch (random points; the grid has about as many nodes)
constexpr double kEvalTargetM = 4.0;         // value + gradient >= 4 M points/s per core at 10^6 points
constexpr double kBuildTargetS = 2.0;        // construction of 10^6 points <= 2 s on 2 cores

struct Step {
    Run run;
    std::string cell_time() const { return run.ok() ? fmt("%.1f", run.seconds) : run.why(); }
    std::string cell_rss() const { return run.ok() ? fmt("%.0f", static_cast<double>(run.maxrss_kib) / 1024.0) : "-"; }
};

Step step(const std::string& cmd, const fs::path& out) {
    std::fprintf(stderr, "bench scale: %s\n", cmd.c_str());
    return Step{run_sh(cmd, out / "cmd.err", out / "cmd.out", kLimit)};
}

// The number after `label` in a --stats text ("point store in 4 slabs": label "point store in ").
std::string after(const std::string& text, const std::string& label) {
    const std::size_t at = text.find(label);
    if (at == std::string::npos) return "?";
    std::size_t e = at + label.size();
    while (e < text.size() && text[e] >= '0' && text[e] <= '9') ++e;
    return text.substr(at + label.size(), e - at - label.size());
}

// User + system CPU seconds of this process so far.
double cpu_seconds() {
    rusage u{};
    ::getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// The nodes of a g^3 grid over the box [lo, hi], x fastest (the order of a slice or a resample).
std::vector<Vec3> grid_nodes(const Vec3& lo, const Vec3& hi, int g) {
    std::vector<Vec3> p;
    p.reserve(static_cast<std::size_t>(g) * static_cast<std::size_t>(g) * static_cast<std::size_t>(g));
    const Vec3 step = (hi - lo) * (1.0 / (g - 1));
    for (int k = 0; k < g; ++k)
        for (int j = 0; j < g; ++j)
            for (int i = 0; i < g; ++i) p.push_back(lo + Vec3{i * step.x, j * step.y, k * step.z});
    return p;
}

// The rows of the field table for the point set `set` of n points: mpu and rbf-grid built here.
void field_rows(const fs::path& set, std::size_t n, Table& t) {
    std::fprintf(stderr, "bench scale: fields of %s\n", set.string().c_str());
    PointSet ps;
    try {
        ps = read_point_set(set.string());
    } catch (const std::exception& e) {
        t.add({fmt("%zu", n), "-", std::string("read: ") + e.what(), "-", "-", "-", "-", "-", "-", "-", "-"});
        return;
    }
    for (FieldKind k : {FieldKind::mpu, FieldKind::rbf_grid}) {
        const std::string name(field_kind_name(k));
        FieldParams params;
        params.kind = k;
        FieldBuildStats st;
        std::unique_ptr<Field> f;
        const double cpu0 = cpu_seconds();
        Stopwatch sw;
        try {
            f = make_field(ps, params, &st);
        } catch (const std::exception& e) {
            t.add({fmt("%zu", n), name, std::string("build: ") + e.what(), "-", "-", "-", "-", "-", "-", "-", "-"});
            continue;
        }
        const double wall = sw.ms() / 1e3, cpu = cpu_seconds() - cpu0;
        const auto b = f->bounds();
        const EvalRate random = eval_rate_one_thread(*f, random_box(b[0], b[1], kEvalPoints, 4242), 3);
        const int g = static_cast<int>(std::lround(std::cbrt(static_cast<double>(kEvalPoints))));
        const EvalRate grid = eval_rate_one_thread(*f, grid_nodes(b[0], b[1], g), 3);
        std::string terms = "-";  // the multiquadric terms an mpu query sums (mean over the random points)
        if (const auto* m = dynamic_cast<const MpuField*>(f.get())) {
            double sum = 0;
            const std::vector<Vec3> q = random_box(b[0], b[1], kEvalPoints / 10, 4242);
            for (const Vec3& x : q) sum += static_cast<double>(m->terms_at(x));
            terms = fmt("%.0f", sum / static_cast<double>(q.size()));
        }
        const bool at_1m = n == 1000000;
        t.add({fmt("%zu", n), name, fmt("%.2f", wall), fmt("%.2f", cpu), fmt("%llu", static_cast<unsigned long long>(st.locals)),
               fmt("%.0f", static_cast<double>(st.memory_bytes) / kMiB), fmt("%.2f (%.2f)", random.per_s / 1e6, random.per_cpu_s / 1e6),
               fmt("%.2f (%.2f)", grid.per_s / 1e6, grid.per_cpu_s / 1e6), fmt("%.1f / %.1f", 100 * random.nan_share, 100 * grid.nan_share),
               terms,
               at_1m ? fmt("build %s, eval %s", wall <= kBuildTargetS ? "PASS" : "FAIL", random.per_s / 1e6 >= kEvalTargetM ? "PASS" : "FAIL")
                     : std::string("-")});
    }
}

}  // namespace

void run_scale(const BenchOptions& o, Report& r) {
    r.section("Scattered isosurfaces as the points grow: in memory, out of core (.mlc), and the VTK peer");
    const fs::path ct = fs::path(o.data_dir) / "vtkjs_LIDC2" / "LIDC2.vti";
    if (!fs::exists(ct)) {
        r.note(ct.string() + " not found (give --data DIR): section skipped.");
        return;
    }
    std::vector<std::size_t> sizes = o.quick ? std::vector<std::size_t>{20000} : std::vector<std::size_t>{100000, 1000000, 3000000};
    if (!o.scattered_sizes.empty()) sizes = parse_scattered_sizes(o.scattered_sizes);
    const bool own_work = o.work_dir.empty();
    const fs::path work = own_work ? fs::temp_directory_path() / fmt("meshless-bench-scale-%d", static_cast<int>(::getpid()))
                                   : fs::path(o.work_dir) / "scale";
    const fs::path out = work / fmt("out-%d", static_cast<int>(::getpid()));
    std::error_code ec;
    fs::create_directories(out, ec);
    const std::string ml = shell_quote(o.meshless);
    const std::string peer = shell_quote(o.python) + " " + shell_quote((fs::path(o.bench_dir) / "scattered_peers.py").string());
    const bool peers = !o.no_peers && step(peer + " --check --method interp", out).run.ok();
    r.note(fmt("Samples of LIDC2.vti (`meshless sample --seed 5`), iso 100.5, all threads; one run per cell; the budget M of the "
               "slab run is two thirds of the one-slab run's peak RSS. Machine: %s. Peer: %s.",
               machine_description().c_str(), peers ? "vtkPointInterpolator (Gaussian, 8 closest) + vtkFlyingEdges3D" : "not run"));
    Table t;
    t.header = {"points", "in memory s", "MiB", "s / point vs first", "convert s", "MiB", ".mlc one slab s", "MiB", "M MiB",
                ".mlc at M s", "MiB", "slabs", "fits copied", "at M / one slab", "same bytes", "peer s", "MiB", "in memory / peer"};
    Table ft;
    ft.header = {"points", "field", "build s", "build CPU s", "locals", "field MiB", "eval random Mpts/s", "eval grid Mpts/s",
                 "NaN % (random / grid)", "terms/query", "targets at 10^6"};
    double first_per_point = 0;
    for (std::size_t n : sizes) {
        std::vector<std::string> row{fmt("%zu", n)};
        const fs::path set = work / fmt("lidc2-%zu.ply", n), store = work / fmt("lidc2-%zu.mlc", n);
        if (!fs::exists(set)) {
            const Step s = step(ml + " sample " + shell_quote(ct.string()) + fmt(" --count %zu --seed 5 -o ", n) + shell_quote(set.string()), out);
            if (!s.run.ok()) {
                row.push_back("sample: " + s.run.why(work.string()));
                row.resize(t.header.size(), "-");
                t.add(row);
                continue;
            }
        }
        const std::string iso = " --iso 100.5 --stats";
        const Step mem = step(ml + " isosurface " + shell_quote(set.string()) + iso + " -o " + shell_quote((out / "a.ply").string()), out);
        row.push_back(mem.cell_time());
        row.push_back(mem.cell_rss());
        const double per_point = mem.run.seconds / static_cast<double>(n);
        if (mem.run.ok() && first_per_point == 0) first_per_point = per_point;
        row.push_back(mem.run.ok() && first_per_point > 0 ? fmt("%.2fx", per_point / first_per_point) : "-");
        fs::remove(store, ec);
        const Step conv = step(ml + " convert " + shell_quote(set.string()) + " -o " + shell_quote(store.string()), out);
        row.push_back(conv.cell_time());
        row.push_back(conv.cell_rss());
        const Step one = step(ml + " isosurface " + shell_quote(store.string()) + iso + " -o " + shell_quote((out / "b.ply").string()), out);
        row.push_back(one.cell_time());
        row.push_back(one.cell_rss());
        const double budget = std::floor(static_cast<double>(one.run.maxrss_kib) / 1024.0 * 2.0 / 3.0);
        row.push_back(one.run.ok() ? fmt("%.0f", budget) : "-");
        const Step slabs = one.run.ok() ? step(ml + " isosurface " + shell_quote(store.string()) + iso + fmt(" --memory %.0fM", budget) +
                                                   " -o " + shell_quote((out / "c.ply").string()),
                                               out)
                                        : Step{};
        row.push_back(one.run.ok() ? slabs.cell_time() : "-");
        row.push_back(slabs.cell_rss());
        row.push_back(slabs.run.ok() ? after(slabs.run.err, "point store in ") : "-");
        row.push_back(slabs.run.ok() ? after(slabs.run.err, "locals (") : "-");
        row.push_back(slabs.run.ok() ? fmt("%.2fx", slabs.run.seconds / one.run.seconds) : "-");
        row.push_back(slabs.run.ok() ? (read_file_bytes(out / "b.ply") == read_file_bytes(out / "c.ply") ? "SAME" : "DIFFERENT") : "-");
        if (peers) {
            const int grid = static_cast<int>(std::lround(std::cbrt(static_cast<double>(n))));
            const Step p = step(peer + " --method interp --input " + shell_quote(set.string()) + fmt(" --iso 100.5 --grid %d --out ", grid) +
                                    shell_quote((out / "peer.ply").string()),
                                out);
            row.push_back(p.cell_time());
            row.push_back(p.cell_rss());
            row.push_back(p.run.ok() && mem.run.ok() ? fmt("%.2fx", mem.run.seconds / p.run.seconds) : "-");
        } else {
            row.resize(t.header.size(), "-");
        }
        t.add(row);
        field_rows(set, n, ft);
        for (const char* f : {"a.ply", "b.ply", "c.ply", "peer.ply"}) fs::remove(out / f, ec);
        if (own_work) fs::remove(set, ec);
        fs::remove(store, ec);
    }
    r.table(t);
    r.note("Targets (the out-of-core goals): the slab run's bytes equal the one-slab run's, at <= 1.5x its time; time per point "
           "within 1.3x from 10^6 to 10^7; the in-memory run no slower than the peer.");
    r.table(ft);
    r.note(fmt("The fields of the same sets built in this process by make_field (all threads; build CPU s: user + system "
               "seconds of the build) with the `fit` defaults; evaluation: value + gradient on one thread, best of 3, in M points per wall second (per CPU second of the thread), at %zu "
               "random points inside the bounds and at the nodes of a regular grid over them (about as many, x fastest); "
               "terms/query: the multiquadric terms an mpu query sums (MpuField::terms_at, mean over a tenth of the random points). "
               "Targets at 10^6 points: construction <= %.0f s (on 2 cores), evaluation >= %.0f M points/s (random points).",
               kEvalPoints, kBuildTargetS, kEvalTargetM));
    fs::remove_all(own_work ? work : out, ec);
}

}  // namespace meshless::bench
