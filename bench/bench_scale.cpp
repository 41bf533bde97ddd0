// `meshless-bench scale`: the scattered-data isosurface (dissertation chapter 5) as the point count
// grows, in memory and out of core, against the VTK peer a user reaches for at these sizes; every
// row a whole process run as users run it (docs/architecture.md, "Fields out of core").
// Per kind of set (--sets: ct, clustered, layered; default ct) and size N (--sizes, default 10^5, 10^6,
// 3x10^6; --quick 2x10^4):
//   1. ct: `meshless sample LIDC2.vti --count N --seed 5` (the chest CT of the data folder: sharp edges);
//      clustered / layered: the gyroid at N positions of that distribution (kernels/scattered_test_sets.hpp:
//      Gaussian blobs at 100:1 density; horizontal layers, sparse in z), written as PLY; cached in the
//      work folder (--work) or a temporary one;
//   2. `meshless isosurface SET.ply --iso V -o a.ply`: the field in memory whole;
//   3. `meshless convert SET.ply -o SET.mlc` (Morton point store), then `isosurface SET.mlc` without a
//      budget (one slab) and with `--memory M`, M = two thirds of the one-slab run's peak RSS: time, peak RSS,
//      slabs and fits copied (its --stats), and whether its bytes equal the one-slab run's;
//   3b. with --ranks R1,R2: `mpirun --oversubscribe -np R meshless isosurface SET.mlc --threads 1`, the
//      largest rank's peak RSS (from --stats) and whether the bytes equal the one-slab run's;
//   4. the peer (bench/scattered_peers.py --method interp): vtkPointInterpolator, Gaussian kernel on
//      the 8 closest points, onto a grid with about as many nodes as points, then vtkFlyingEdges3D.
// Ratios: time and peak RSS per point against the smallest size (linearity), the field's regularised locals
// (from the one-slab run's --stats), the slab run against the one-slab
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
#include "formats/point_set_writer.hpp"
#include "kernels/scattered_test_sets.hpp"
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

// The number after the last occurrence of `label` ... up to `stop` in a --stats text, as a double (NaN: absent).
double number_after(const std::string& text, const std::string& label) {
    const std::size_t at = text.find(label);
    if (at == std::string::npos) return std::nan("");
    return std::strtod(text.c_str() + at + label.size(), nullptr);
}

// The largest "peak RSS X MiB" of a per-rank --stats line (0: none).
double largest_rank_rss(const std::string& text) {
    double most = 0;
    for (std::size_t at = text.find("peak RSS "); at != std::string::npos; at = text.find("peak RSS ", at + 1))
        most = std::max(most, std::strtod(text.c_str() + at + 9, nullptr));
    return most;
}

// One kind of point set the scale rows run on.
struct SetKind {
    std::string name;   // "ct", "clustered", "layered"
    double iso = 0;
    std::string what;   // for the note
};

std::vector<SetKind> parse_set_kinds(const std::string& list) {
    std::vector<SetKind> kinds;
    std::size_t from = 0;
    const std::string l = list.empty() ? "ct" : list;
    while (from <= l.size()) {
        const std::size_t comma = std::min(l.find(',', from), l.size());
        const std::string w = l.substr(from, comma - from);
        if (w == "ct") kinds.push_back({w, 100.5, "samples of LIDC2.vti (`meshless sample --seed 5`: a CT, sharp edges), iso 100.5"});
        else if (w == "clustered" || w == "layered")
            kinds.push_back({w, default_iso(AnalyticField::gyroid),
                             "the gyroid in [-1,1]^3 at " + w + " positions (kernels/scattered_test_sets.hpp: " +
                                 (w == "clustered" ? std::string("Gaussian blobs, 100:1 density") : std::string("horizontal layers, 8-11x sparser in z")) +
                                 fmt("), iso %g", default_iso(AnalyticField::gyroid))});
        else throw std::invalid_argument("--sets: expected ct, clustered or layered (got '" + w + "')");
        from = comma + 1;
    }
    return kinds;
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
void field_rows(const std::string& kind, const fs::path& set, std::size_t n, Table& t) {
    std::fprintf(stderr, "bench scale: fields of %s\n", set.string().c_str());
    PointSet ps;
    try {
        ps = read_point_set(set.string());
    } catch (const std::exception& e) {
        t.add({kind, fmt("%zu", n), "-", std::string("read: ") + e.what(), "-", "-", "-", "-", "-", "-", "-", "-"});
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
            t.add({kind, fmt("%zu", n), name, std::string("build: ") + e.what(), "-", "-", "-", "-", "-", "-", "-", "-"});
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
        t.add({kind, fmt("%zu", n), name, fmt("%.2f", wall), fmt("%.2f", cpu), fmt("%llu", static_cast<unsigned long long>(st.locals)),
               fmt("%.0f", static_cast<double>(st.memory_bytes) / kMiB), fmt("%.2f (%.2f)", random.per_s / 1e6, random.per_cpu_s / 1e6),
               fmt("%.2f (%.2f)", grid.per_s / 1e6, grid.per_cpu_s / 1e6), fmt("%.1f / %.1f", 100 * random.nan_share, 100 * grid.nan_share),
               terms,
               at_1m ? fmt("build %s, eval %s", wall <= kBuildTargetS ? "PASS" : "FAIL", random.per_s / 1e6 >= kEvalTargetM ? "PASS" : "FAIL")
                     : std::string("-")});
    }
}

}  // namespace

std::vector<int> parse_rank_counts(const std::string& list) {
    std::vector<int> v;
    std::size_t from = 0;
    while (!list.empty() && from <= list.size()) {
        const std::size_t comma = std::min(list.find(',', from), list.size());
        const std::string w = list.substr(from, comma - from);
        char* end = nullptr;
        const long k = std::strtol(w.c_str(), &end, 10);
        if (w.empty() || *end != '\0') throw std::invalid_argument("--ranks: expected counts like 2,4 (got '" + w + "')");
        v.push_back(static_cast<int>(k));
        from = comma + 1;
    }
    return v;
}

void check_scale_options(const BenchOptions& o) {
    (void)parse_set_kinds(o.scale_sets);
    for (int ranks : parse_rank_counts(o.scale_ranks))
        if (ranks < 1 || ranks > 64) throw std::invalid_argument("--ranks: expected counts 1..64");
}

void run_scale(const BenchOptions& o, Report& r) {
    r.section("Scattered isosurfaces as the points grow: in memory, out of core (.mlc), and the VTK peer");
    const fs::path ct = fs::path(o.data_dir) / "vtkjs_LIDC2" / "LIDC2.vti";
    const std::vector<SetKind> kinds = parse_set_kinds(o.scale_sets);
    const std::vector<int> rank_counts = parse_rank_counts(o.scale_ranks);
    const bool wants_ct = std::any_of(kinds.begin(), kinds.end(), [](const SetKind& k) { return k.name == "ct"; });
    if (wants_ct && !fs::exists(ct)) {
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
    std::string sets;
    for (const SetKind& k : kinds) sets += (sets.empty() ? "" : "; ") + k.name + ": " + k.what;
    r.note(fmt("Sets: %s. All threads; one run per cell; the budget M of the "
               "slab run is two thirds of the one-slab run's peak RSS. Machine: %s. Peer: %s.",
               sets.c_str(), machine_description().c_str(), peers ? "vtkPointInterpolator (Gaussian, 8 closest) + vtkFlyingEdges3D" : "not run"));
    Table t;
    t.header = {"set", "points", "in memory s", "MiB", "s / point vs first", "MiB / point vs first", "locals", "regularised %",
                "convert s", "MiB", ".mlc one slab s", "MiB", "M MiB",
                ".mlc at M s", "MiB", "slabs", "fits copied", "at M / one slab", "same bytes", "peer s", "MiB", "in memory / peer"};
    Table mt;
    mt.header = {"set", "points", "ranks", "time s", "largest rank peak RSS MiB", "vs one process", "points loaded by the ranks",
                 "same bytes"};
    Table ft;
    ft.header = {"set", "points", "field", "build s", "build CPU s", "locals", "field MiB", "eval random Mpts/s", "eval grid Mpts/s",
                 "NaN % (random / grid)", "terms/query", "targets at 10^6"};
    for (const SetKind& kind : kinds) {
    double first_per_point = 0, first_rss_per_point = 0;
    for (std::size_t n : sizes) {
        std::vector<std::string> row{kind.name, fmt("%zu", n)};
        const std::string stem = kind.name == "ct" ? fmt("lidc2-%zu", n) : fmt("gyroid-%s-%zu", kind.name.c_str(), n);
        const fs::path set = work / (stem + ".ply"), store = work / (stem + ".mlc");
        if (!fs::exists(set)) {
            std::string why;
            if (kind.name == "ct") {
                const Step s = step(ml + " sample " + shell_quote(ct.string()) + fmt(" --count %zu --seed 5 -o ", n) + shell_quote(set.string()), out);
                if (!s.run.ok()) why = s.run.why(work.string());
            } else {
                try {
                    ScatteredSetSpec spec;
                    spec.field = AnalyticField::gyroid;
                    spec.distribution = *parse_scatter_distribution(kind.name);
                    spec.count = n;
                    spec.seed = 5;
                    write_point_set_ply(set.string(), make_scattered_set(spec));
                } catch (const std::exception& e) {
                    why = e.what();
                }
            }
            if (!why.empty()) {
                row.push_back("set: " + why);
                row.resize(t.header.size(), "-");
                t.add(row);
                continue;
            }
        }
        const std::string iso = fmt(" --iso %.17g --stats", kind.iso);
        const Step mem = step(ml + " isosurface " + shell_quote(set.string()) + iso + " -o " + shell_quote((out / "a.ply").string()), out);
        row.push_back(mem.cell_time());
        row.push_back(mem.cell_rss());
        const double per_point = mem.run.seconds / static_cast<double>(n);
        const double rss_per_point = static_cast<double>(mem.run.maxrss_kib) / static_cast<double>(n);
        if (mem.run.ok() && first_per_point == 0) {
            first_per_point = per_point;
            first_rss_per_point = rss_per_point;
        }
        row.push_back(mem.run.ok() && first_per_point > 0 ? fmt("%.2fx", per_point / first_per_point) : "-");
        row.push_back(mem.run.ok() && first_rss_per_point > 0 ? fmt("%.2fx", rss_per_point / first_rss_per_point) : "-");
        const std::size_t locals_col = row.size();
        row.push_back("-");
        row.push_back("-");
        fs::remove(store, ec);
        const Step conv = step(ml + " convert " + shell_quote(set.string()) + " -o " + shell_quote(store.string()), out);
        row.push_back(conv.cell_time());
        row.push_back(conv.cell_rss());
        const Step one = step(ml + " isosurface " + shell_quote(store.string()) + iso + " -o " + shell_quote((out / "b.ply").string()), out);
        row.push_back(one.cell_time());
        row.push_back(one.cell_rss());
        if (one.run.ok()) {  // the field's locals and the regularised share, from the one-slab run's --stats
            const double locals = number_after(one.run.err, "loaded in all), ");
            const double reg = number_after(one.run.err, "fits copied from the slab before, ");
            if (std::isfinite(locals) && locals > 0) {
                row[locals_col] = fmt("%.0f", locals);
                if (std::isfinite(reg)) row[locals_col + 1] = fmt("%.2f", 100 * reg / locals);
            }
        }
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
        // the store shared out across mpirun ranks, one thread each (each its own layers and their points)
        for (int ranks : one.run.ok() ? rank_counts : std::vector<int>{}) {
            const Step m = step("mpirun --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " " + ml + " isosurface " +
                                    shell_quote(store.string()) + iso + " --threads 1 -o " + shell_quote((out / "d.ply").string()),
                                out);
            const double most = m.run.ok() ? largest_rank_rss(m.run.err) : 0;
            mt.add({kind.name, fmt("%zu", n), std::to_string(ranks), m.cell_time(), m.run.ok() ? fmt("%.0f", most) : "-",
                    m.run.ok() && one.run.maxrss_kib > 0 ? fmt("%.2fx", most * 1024.0 / static_cast<double>(one.run.maxrss_kib)) : "-",
                    m.run.ok() ? after(m.run.err, "loaded at once (") : "-",
                    m.run.ok() ? (read_file_bytes(out / "b.ply") == read_file_bytes(out / "d.ply") ? "SAME" : "DIFFERENT") : "-"});
        }
        if (peers) {
            const int grid = static_cast<int>(std::lround(std::cbrt(static_cast<double>(n))));
            const Step p = step(peer + " --method interp --input " + shell_quote(set.string()) + fmt(" --iso %.17g --grid %d --out ", kind.iso, grid) +
                                    shell_quote((out / "peer.ply").string()),
                                out);
            row.push_back(p.cell_time());
            row.push_back(p.cell_rss());
            row.push_back(p.run.ok() && mem.run.ok() ? fmt("%.2fx", mem.run.seconds / p.run.seconds) : "-");
        } else {
            row.resize(t.header.size(), "-");
        }
        t.add(row);
        field_rows(kind.name, set, n, ft);
        for (const char* f : {"a.ply", "b.ply", "c.ply", "d.ply", "peer.ply"}) fs::remove(out / f, ec);
        if (own_work) fs::remove(set, ec);
        fs::remove(store, ec);
    }
    }
    r.table(t);
    r.note("Targets (the out-of-core goals): the slab run's bytes equal the one-slab run's, at <= 1.5x its time; time per point "
           "within 1.3x from 10^6 to 10^7; the in-memory run no slower than the peer.");
    if (!rank_counts.empty()) {
        r.table(mt);
        r.note("The same stores under `mpirun --oversubscribe -np R meshless isosurface SET.mlc --threads 1` "
               "(stream/scattered_store_ranks.hpp): each rank its own stencil layers along z and the points they need; the "
               "largest rank's peak RSS (its own getrusage, from --stats) against the one-slab run's; the points loaded: all "
               "the ranks' loads summed (halos counted again); same bytes: against the one-slab run.");
    }
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
