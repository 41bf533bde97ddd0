// meshless-bench process: the numbers, measured on whole processes as a user runs them. Every
// row spawns the `meshless` binary (BenchOptions::meshless) through /bin/sh -c, best of N wall-clock
// runs (steady clock around fork .. wait4), peak resident memory from wait4's rusage (ru_maxrss: for
// a shell pipeline the largest single process of it, the shell reaping its children). Baselines are
// measured in the same run: VTK's vtkFlyingEdges3D filter time (bench/flying_edges.py, one thread),
// the in-process command for pipes, --threads 1 for --threads 2, paradigm (C) for paradigm (A).
//
// The harness knows command lines only, never the internals of the commands, so it measures any
// build of `meshless`: a command that fails (an option the binary does not have yet, a crash) is an
// "n/a (reason)" row and the run goes on.
//
// Inputs, made once into the work folder (--work DIR, kept and reused; default a temporary folder
// removed at the end): the lung-sized CT = LIDC2 (256x256x133 uint8, ../shared/data/vtkjs_LIDC2)
// upsampled x2 by `meshless synth --upsample 2` (trilinear) into lung.mlb (511x511x265), the same
// voxels as lung.raw with a detached NRRD header lung.nhdr (written here from the store), and
// synthetic oriented point sets (points on a sphere, binary PLY) for the splat rows.
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <regex>
#include <sstream>

#include "bench/bench_common.hpp"
#include "bench/platform_ceiling.hpp"
#include "formats/json.hpp"
#include "formats/ply.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_slice_source.hpp"

namespace meshless::bench {

namespace {

namespace fs = std::filesystem;

constexpr double kMiB = 1024.0 * 1024.0;
constexpr double kPi = 3.14159265358979323846;

std::string first_line(const std::string& s) {
    std::string t = s;
    while (!t.empty() && (t.back() == '\n' || t.back() == '\r')) t.pop_back();
    const auto nl = t.find('\n');
    return nl == std::string::npos ? t : t.substr(0, nl);
}

std::uint64_t file_bytes(const fs::path& p) {
    std::error_code ec;
    const auto n = fs::file_size(p, ec);
    return ec ? 0 : n;
}

/// Best of n runs of one command: the fastest successful run (its stderr and RSS); the first
/// failure ends the series and is returned instead.
struct Timed {
    bool ok = false;
    double seconds = std::numeric_limits<double>::infinity();
    long maxrss_kib = 0;  ///< the largest over the runs
    std::string err;      ///< stderr of the fastest run
    std::string why;      ///< failure reason
};

Timed best_of(const std::string& cmd, int n, const fs::path& work) {
    Timed t;
    std::fprintf(stderr, "bench process: %s\n", cmd.c_str());
    for (int i = 0; i < n; ++i) {
        const Run r = run_sh(cmd, work / "stderr.txt");
        if (!r.ok()) {
            t.ok = false;
            t.why = r.why(work.string());
            return t;
        }
        t.ok = true;
        t.maxrss_kib = std::max(t.maxrss_kib, r.maxrss_kib);
        if (r.seconds < t.seconds) {
            t.seconds = r.seconds;
            t.err = r.err;
        }
    }
    return t;
}

// ---- comparing outputs --------------------------------------------------------------------------

/// A binary PLY's vertex records: record size from the header's vertex properties, body after end_header.
struct PlyBody {
    bool ok = false;
    std::size_t record = 0;
    std::string header, body;
};

PlyBody read_ply_body(const fs::path& p) {
    PlyBody b;
    const std::string all = read_file_bytes(p);
    try {
        const PlyHeader h = parse_ply_header(all, p.string());  // the codec's header parser
        const int vi = h.find("vertex");
        if (h.encoding == PlyEncoding::ascii || vi < 0 || h.elements[vi].has_lists()) return b;
        b.header = all.substr(0, h.header_bytes);
        b.body = all.substr(h.header_bytes);
        b.record = h.elements[vi].min_record_bytes();
    } catch (const FormatError&) {
        return b;
    }
    b.ok = b.record > 0 && b.body.size() % b.record == 0;
    return b;
}

/// "SAME" (identical bytes), "SAME points (...)" (identical vertex records, header or order differs),
/// "DIFFERENT (...)", or "n/a (...)" when a file is missing.
std::string compare_points(const fs::path& a, const fs::path& b) {
    if (!fs::exists(a) || !fs::exists(b)) return "n/a (missing output)";
    const std::string sa = read_file_bytes(a), sb = read_file_bytes(b);
    if (sa == sb) return "SAME";
    PlyBody pa = read_ply_body(a), pb = read_ply_body(b);
    if (!pa.ok || !pb.ok) return "DIFFERENT (not comparable as binary PLY)";
    if (pa.record != pb.record) return "DIFFERENT (vertex layouts differ)";
    const std::size_t na = pa.body.size() / pa.record, nb = pb.body.size() / pb.record;
    if (na != nb) return fmt("DIFFERENT (%zu vs %zu points)", na, nb);
    if (pa.body == pb.body) return "SAME points (headers differ)";
    auto sorted = [](const PlyBody& p) {
        std::vector<std::string_view> v;
        v.reserve(p.body.size() / p.record);
        for (std::size_t i = 0; i < p.body.size(); i += p.record) v.emplace_back(p.body.data() + i, p.record);
        std::sort(v.begin(), v.end());
        return v;
    };
    if (sorted(pa) == sorted(pb)) return "SAME points (in another order)";
    return fmt("DIFFERENT (%zu points each, records differ)", na);
}

// ---- formatting ---------------------------------------------------------------------------------

std::string secs(double s) { return fmt("%.3f", s); }
std::string mib(long kib) { return kib > 0 ? fmt("%.0f", kib / 1024.0) : std::string("-"); }
std::string na(const std::string& why) { return "n/a (" + why + ")"; }
/// "0.42x (target <= 0.5: PASS)"; target_le: the ratio must be <= target, else >= target.
std::string verdict(double ratio, double target, bool target_le) {
    const bool pass = target_le ? ratio <= target : ratio >= target;
    return fmt("%s %.2f: %s", target_le ? "<=" : ">=", target, pass ? "PASS" : "FAIL");
}

/// Seconds the command reported itself on stderr, or nullopt: an "extraction X s" figure when the
/// command gives one (extraction alone), else isosurface --stats' "..., 0.123 s on 1 thread(s)" (the
/// in-process pipeline: extract + project + handing the points to the writer; not reading the volume).
struct Reported {
    double seconds = 0;
    bool extraction = false;  ///< the figure is labelled as extraction alone
};
std::optional<Reported> reported_seconds(const std::string& err) {
    std::smatch m;
    static const std::regex extraction(R"(extraction[^0-9\n]*([0-9]+(?:\.[0-9]+)?) ?s\b)");
    static const std::regex on(R"(([0-9]+(?:\.[0-9]+)?) s on )");
    if (std::regex_search(err, m, extraction)) return Reported{std::stod(m[1]), true};
    if (std::regex_search(err, m, on)) return Reported{std::stod(m[1]), false};
    return std::nullopt;
}

std::optional<long long> reported_active_cells(const std::string& err) {
    std::smatch m;
    static const std::regex re(R"(([0-9]+) active cells)");
    if (std::regex_search(err, m, re)) return std::stoll(m[1]);
    return std::nullopt;
}

/// Splat render time per frame from `splat --turntable N` ("... 12.34 ms/frame").
std::optional<double> reported_ms_per_frame(const std::string& err) {
    std::smatch m;
    static const std::regex re(R"(([0-9]+(?:\.[0-9]+)?) ms/frame)");
    if (std::regex_search(err, m, re)) return std::stod(m[1]);
    return std::nullopt;
}

// ---- inputs -------------------------------------------------------------------------------------

struct Lung {
    bool ok = false;
    std::string why;           ///< why it could not be made
    fs::path mlb, raw, nhdr;   ///< the store, the voxels, the NRRD header naming them
    GridSpec grid;
    std::string label;
};

/// Writes lung.raw + lung.nhdr (detached NRRD) with the voxels and grid of the store.
void write_raw_and_header(const fs::path& mlb, const fs::path& raw, const fs::path& nhdr, GridSpec& grid) {
    const Volume v = read_brick_store_volume(mlb.string());
    if (v.type != SampleType::u8) throw IoError(mlb.string() + ": expected uint8 samples");
    grid = v.grid;
    {
        const fs::path tmp = raw.string() + ".tmp";
        std::ofstream f(tmp, std::ios::binary);
        f.write(reinterpret_cast<const char*>(v.bytes.data()), static_cast<std::streamsize>(v.bytes.size()));
        if (!f) throw IoError(tmp.string() + ": cannot write");
        f.close();
        fs::rename(tmp, raw);
    }
    const auto& g = v.grid;
    std::string h = "NRRD0004\n# the lung-sized CT of meshless-bench process (meshless synth --upsample of LIDC2)\n";
    h += "type: uint8\ndimension: 3\n";
    h += fmt("sizes: %lld %lld %lld\n", static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]),
             static_cast<long long>(g.dims[2]));
    h += "space dimension: 3\n";
    h += fmt("space directions: (%.17g,0,0) (0,%.17g,0) (0,0,%.17g)\n", g.spacing[0], g.spacing[1], g.spacing[2]);
    h += fmt("space origin: (%.17g,%.17g,%.17g)\n", g.origin[0], g.origin[1], g.origin[2]);
    h += "endian: little\nencoding: raw\n";
    h += "data file: " + raw.filename().string() + "\n";
    const fs::path tmp = nhdr.string() + ".tmp";
    std::ofstream f(tmp, std::ios::binary);
    f << h;
    f.close();
    if (!f) throw IoError(tmp.string() + ": cannot write");
    fs::rename(tmp, nhdr);
}

/// The lung-sized volume in `work` (made when missing); `scratch` takes the commands' stderr.
Lung make_lung(const BenchOptions& o, const fs::path& work, const fs::path& scratch, int factor, Report& r) {
    Lung l;
    const fs::path lidc = fs::path(o.data_dir) / "vtkjs_LIDC2" / "LIDC2.vti";
    if (!fs::exists(lidc)) {
        l.why = lidc.string() + " not found (give --data DIR)";
        return l;
    }
    const std::string tag = fmt("lung_x%d", factor);
    l.mlb = work / (tag + ".mlb");
    l.raw = work / (tag + ".raw");
    l.nhdr = work / (tag + ".nhdr");
    if (!fs::exists(l.mlb)) {
        const std::string cmd = shell_quote(o.meshless) + " synth --upsample " + std::to_string(factor) + " " +
                                shell_quote(lidc.string()) + " -o " + shell_quote(l.mlb.string());
        std::fprintf(stderr, "bench process: %s\n", cmd.c_str());
        const Run s = run_sh(cmd, scratch / "stderr.txt");
        if (!s.ok()) {
            l.why = "meshless synth failed: " + s.why();
            return l;
        }
        r.note(fmt("Made `meshless synth --upsample %d LIDC2.vti -o %s` in %.1f s.", factor,
                   l.mlb.filename().c_str(), s.seconds));
    }
    try {
        if (!fs::exists(l.raw) || !fs::exists(l.nhdr)) write_raw_and_header(l.mlb, l.raw, l.nhdr, l.grid);
        else l.grid = open_brick_store_slices(l.mlb.string())->grid();
    } catch (const std::exception& e) {
        l.why = e.what();
        return l;
    }
    l.ok = true;
    l.label = fmt("LIDC2 x%d (%lldx%lldx%lld uint8, %.0f MiB)", factor, static_cast<long long>(l.grid.dims[0]),
                  static_cast<long long>(l.grid.dims[1]), static_cast<long long>(l.grid.dims[2]),
                  static_cast<double>(l.grid.voxel_count()) / kMiB);
    return l;
}

/// n oriented points on a sphere (centre 0.5, radius 0.4, in the unit cube) as a binary PLY with
/// the splat fields of `meshless isosurface` (x y z nx ny nz radius value) and the unit cube as the
/// framing bounds. Rings of latitude, points in order along each ring (spatially coherent, like an
/// extracted surface); splat radius = the mean point spacing. Reused when present with the right size.
fs::path sphere_points(const fs::path& work, std::uint64_t n) {
    const fs::path p = work / fmt("sphere_%llu.ply", static_cast<unsigned long long>(n));
    PlyHeader h;
    h.encoding = PlyEncoding::binary_little_endian;
    h.comments = {"meshless-bench synthetic sphere (splat benchmark)", "bounds_lo 0,0,0", "bounds_hi 1,1,1"};
    PlyElement v{"vertex", n, {}, 0};
    for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "radius", "value"})
        v.props.push_back({name, StoredType::f32, false, StoredType::u8});
    h.elements.push_back(std::move(v));
    if (file_bytes(p) == format_ply_header(h, false).size() + n * 32) return p;
    std::fprintf(stderr, "bench process: writing %llu points to %s\n", static_cast<unsigned long long>(n), p.c_str());
    const double R = 0.4, spacing = std::sqrt(4 * kPi * R * R / static_cast<double>(n));
    const auto rings = static_cast<std::int64_t>(std::max(1.0, std::round(std::sqrt(kPi * static_cast<double>(n) / 4))));
    PlyWriter f(p.string(), std::move(h), PlyCounts::declared);  // the codec's writer (temporary + rename)
    std::vector<float> buf;
    buf.reserve(8 * 65536);
    std::uint64_t done = 0;
    for (std::int64_t j = 0; j < rings; ++j) {
        // points up to ring j's lower edge in proportion to the cap area (1 - cos theta) / 2
        const double edge = kPi * static_cast<double>(j + 1) / static_cast<double>(rings);
        const auto upto = j + 1 == rings ? n
                                         : static_cast<std::uint64_t>(std::llround(static_cast<double>(n) *
                                                                                   (1 - std::cos(edge)) / 2));
        const std::uint64_t m = upto - done;
        const double theta = kPi * (static_cast<double>(j) + 0.5) / static_cast<double>(rings);
        for (std::uint64_t i = 0; i < m; ++i) {
            const double phi = 2 * kPi * (static_cast<double>(i) + 0.5 * static_cast<double>(j & 1)) / static_cast<double>(m);
            const double nx = std::sin(theta) * std::cos(phi), ny = std::sin(theta) * std::sin(phi), nz = std::cos(theta);
            const float rec[8] = {static_cast<float>(0.5 + R * nx), static_cast<float>(0.5 + R * ny),
                                  static_cast<float>(0.5 + R * nz), static_cast<float>(nx), static_cast<float>(ny),
                                  static_cast<float>(nz), static_cast<float>(spacing), 100.5f};
            buf.insert(buf.end(), rec, rec + 8);
            if (buf.size() >= 8 * 65536) {
                f.append(buf.data(), buf.size() * sizeof(float));
                buf.clear();
            }
        }
        done = upto;
    }
    f.append(buf.data(), buf.size() * sizeof(float));
    f.commit();
    return p;
}

// ---- the rows -----------------------------------------------------------------------------------

struct Ctx {
    const BenchOptions& o;
    Report& r;
    fs::path work;  ///< the run's own output folder (outputs, stderr files), removed at the end
    int reps;
    std::string m;  ///< quoted meshless path
    Timed run(const std::string& cmd) const { return best_of(cmd, reps, work); }
    std::string out(const std::string& name) const { return shell_quote((work / name).string()); }
};

const std::vector<std::string> kProcessHeader = {"row", "seconds", "peak RSS MiB", "baseline", "baseline s", "ratio",
                                                 "target", "output"};

/// No baseline / no target.
constexpr double kNone = -1;

/// One result row: name, the timed run, the baseline's name and seconds (kNone: none) and the target
/// (kNone: none). ratio = seconds / baseline, or baseline / seconds with speedup = true.
void add_row(Table& t, const std::string& name, const Timed& x, const std::string& base_name, double base_s,
             double target, bool target_le, bool speedup = false, const std::string& output = "") {
    const std::string base = base_s > 0 ? secs(base_s) : std::string("-");
    if (!x.ok) {
        t.add({name, na(x.why), "-", base_name, base, "-", "-", output});
        return;
    }
    std::string ratio = "-", tgt = target > 0 ? fmt("%s %.2f", target_le ? "<=" : ">=", target) : std::string("-");
    if (base_s > 0) {
        const double q = speedup ? base_s / x.seconds : x.seconds / base_s;
        ratio = fmt("%.2fx", q);
        if (target > 0) tgt = verdict(q, target, target_le);
    }
    t.add({name, secs(x.seconds), mib(x.maxrss_kib), base_name, base, ratio, tgt, output});
}

/// The isovalues of part (a): n values evenly spread over 40.5 .. 200.5, each between grey levels.
std::vector<double> part_a_isovalues(int n) {
    std::vector<double> v;
    for (int k = 0; k < n; ++k)
        v.push_back(n == 1 ? 100.5 : 40.5 + std::round(160.0 * k / (n - 1)));
    return v;
}

struct FeResult {
    bool ok = false;
    std::string why, version;
    double sum_best = 0;
};

/// vtkFlyingEdges3D filter time alone (volume already in memory, one thread), best of reps per
/// isovalue, summed, by bench/flying_edges.py under o.python.
FeResult flying_edges(const Ctx& c, const Lung& l, const std::vector<double>& isos) {
    FeResult fe;
    const fs::path script = fs::path(c.o.bench_dir) / "flying_edges.py";
    if (!fs::exists(script)) {
        fe.why = "flying_edges.py not found in " + c.o.bench_dir + " (give --bench-dir)";
        return fe;
    }
    const Run probe = run_sh(shell_quote(c.o.python) + " -c 'import vtk'", c.work / "stderr.txt");
    if (!probe.ok()) {
        fe.why = "`import vtk` fails under " + c.o.python + " (apt-get install python3-vtk9)";
        return fe;
    }
    std::string iso_list;
    for (double v : isos) iso_list += (iso_list.empty() ? "" : ",") + fmt("%g", v);
    const auto& g = l.grid;
    const std::string cmd = shell_quote(c.o.python) + " " + shell_quote(script.string()) + " --raw " + shell_quote(l.raw.string()) +
                            fmt(" --dims %lld,%lld,%lld --type uint8 --spacing %.17g,%.17g,%.17g --origin %.17g,%.17g,%.17g",
                                static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]),
                                static_cast<long long>(g.dims[2]), g.spacing[0], g.spacing[1], g.spacing[2],
                                g.origin[0], g.origin[1], g.origin[2]) +
                            " --isos " + iso_list + fmt(" --reps %d", c.reps);
    std::fprintf(stderr, "bench process: %s\n", cmd.c_str());
    const Run run = run_sh(cmd, c.work / "stderr.txt", c.work / "fe.json");
    if (!run.ok()) {
        fe.why = "flying_edges.py failed: " + run.why();
        return fe;
    }
    try {
        const Json j = parse_json(run.out, "flying_edges.py output");
        const Json* per = j.find("per_iso");
        if (!per || !per->is_array() || per->arr.size() != isos.size()) throw FormatError("no per_iso array");
        for (const Json& e : per->arr) {
            const Json* b = e.find("best_seconds");
            if (!b) b = e.find("seconds");
            if (!b || !b->is_number()) throw FormatError("per_iso entry without seconds");
            fe.sum_best += b->num;
        }
        const Json* v = j.find("vtk_version");
        const Json* be = j.find("smp_backend");
        fe.version = (v && v->is_string() ? v->str : std::string("?")) + ", " + (be && be->is_string() ? be->str : std::string("?"));
        fe.ok = true;
    } catch (const std::exception& e) {
        fe.why = std::string("cannot read flying_edges.py output: ") + e.what();
    }
    return fe;
}

/// Sum over isovalues of best-of-N runs; the first failure makes the whole sum n/a.
struct SumTimed {
    Timed total;                     ///< seconds = sum of the best runs, RSS = the largest
    std::optional<double> reported;  ///< sum of the seconds the command reported itself (--stats)
    bool reported_extraction = false;  ///< ... labelled as extraction alone
};

SumTimed sum_over(const Ctx& c, const std::vector<double>& isos, const std::function<std::string(double, int)>& cmd) {
    SumTimed s;
    s.total.ok = true;
    s.total.seconds = 0;
    double rep = 0;
    bool have_rep = true, extraction = true;
    for (std::size_t i = 0; i < isos.size(); ++i) {
        const Timed t = c.run(cmd(isos[i], static_cast<int>(i)));
        if (!t.ok) return {t, std::nullopt};
        s.total.seconds += t.seconds;
        s.total.maxrss_kib = std::max(s.total.maxrss_kib, t.maxrss_kib);
        if (auto x = reported_seconds(t.err)) {
            rep += x->seconds;
            extraction = extraction && x->extraction;
        } else {
            have_rep = false;
        }
    }
    if (have_rep) s.reported = rep;
    s.reported_extraction = have_rep && extraction;
    return s;
}

void part_a(const Ctx& c, const Lung& l, const std::vector<double>& isos) {
    c.r.section("(a) isosurface vs VTK Flying Edges: " + l.label);
    const FeResult fe = flying_edges(c, l, isos);
    std::string iso_text;
    for (double v : isos) iso_text += (iso_text.empty() ? "" : ", ") + fmt("%g", v);
    c.r.note(fmt("%zu isovalues (%s), each a separate process, best of %d; seconds = sum over the isovalues. "
                 "`meshless isosurface %s --iso V -o out.ply --threads 1 --stats` reads the volume, extracts, "
                 "projects and writes the PLY. Baseline: vtkFlyingEdges3D filter time alone, on the volume already in "
                 "memory, normals on, one thread (bench/flying_edges.py, best of %d per isovalue, summed)%s. The "
                 "--stats row is the time the command reports itself: extraction alone when it labels a figure so, "
                 "else its in-process pipeline (extract + project + handing points to the PLY writer, without reading "
                 "the volume or starting the process).",
                 isos.size(), iso_text.c_str(), c.reps, l.nhdr.filename().c_str(), c.reps,
                 fe.ok ? (": VTK " + fe.version).c_str() : ""));
    if (!fe.ok) c.r.note("VTK rows skipped: " + fe.why);
    const double base = fe.ok ? fe.sum_best : kNone;
    const std::string vol = shell_quote(l.nhdr.string());
    Table t{kProcessHeader, {}};
    const SumTimed ply = sum_over(c, isos, [&](double v, int i) {
        return c.m + " isosurface " + vol + fmt(" --iso %g", v) + " -o " + c.out(fmt("a_%d.ply", i)) + " --threads 1 --stats";
    });
    add_row(t, "isosurface -o PLY", ply.total, "Flying Edges filter", base, 0.5, true);
    if (ply.total.ok) {
        Timed ex = ply.total;
        if (ply.reported) {
            ex.seconds = *ply.reported;
            ex.maxrss_kib = 0;
        } else {
            ex.ok = false;
            ex.why = "isosurface --stats reports no time";
        }
        add_row(t, ply.reported_extraction ? "  its extraction alone (--stats)" : "  its in-process pipeline (--stats)", ex,
                "Flying Edges filter", base, 0.3, true);
    }
    const SumTimed png = sum_over(c, isos, [&](double v, int i) {
        return c.m + " isosurface " + vol + fmt(" --iso %g", v) + " -o " + c.out(fmt("a_%d.ply", i)) + " --png " +
               c.out(fmt("a_%d.png", i)) + " --threads 1 --stats";
    });
    add_row(t, "isosurface -o PLY --png", png.total, "Flying Edges filter", base, 0.7, true);
    c.r.table(t);
}

void part_b(const Ctx& c, const Lung& l, double iso) {
    c.r.section(fmt("(b) pipes vs in-process: %s, iso %g", l.label.c_str(), iso));
    c.r.note("`meshless generate VOL --iso V --threads 1 | meshless project --threads 1 | meshless write -o pipe.ply` "
             "(a /bin/sh pipeline; its peak RSS is the largest of the three processes) vs "
             "`meshless isosurface VOL --iso V -o inproc.ply --threads 1`; output = byte comparison of the two PLY files.");
    const std::string vol = shell_quote(l.nhdr.string()), iso_s = fmt(" --iso %g", iso);
    const Timed in = c.run(c.m + " isosurface " + vol + iso_s + " -o " + c.out("b_inproc.ply") + " --threads 1");
    const Timed pipe = c.run(c.m + " generate " + vol + iso_s + " --threads 1 | " + c.m + " project --threads 1 | " + c.m +
                             " write -o " + c.out("b_pipe.ply"));
    Table t{kProcessHeader, {}};
    add_row(t, "isosurface (in-process)", in, "-", kNone, kNone, true);
    add_row(t, "generate | project | write", pipe, "in-process", in.ok ? in.seconds : kNone,
            1.3, true, false,
            in.ok && pipe.ok ? compare_points(c.work / "b_inproc.ply", c.work / "b_pipe.ply") : std::string("-"));
    c.r.table(t);
}

/// What two threads can gain on this machine for the work around the computing (bench/platform_ceiling.hpp).
void part_c_ceilings(const Ctx& c, const Lung& l) {
    c.r.note("Platform ceilings, measured in this process (best of the runs, 1 thread doing all vs 2 threads doing half "
             "each; speedup = 1-thread / 2-thread seconds): the most that two threads can gain on this machine for the "
             "work a whole process does besides computing. `isosurface` reads its volume through the page cache twice "
             "(the block min/max pass that frames the surface, then the slabs) and writes its PLY through it; the "
             "picture's buffers and footprint spool are fresh memory, faulted in and zeroed by the kernel.");
    Table t{{"work", "MiB", "1 thread s", "2 threads s", "speedup", "GiB/s (1 thread)"}, {}};
    auto add = [&](const std::string& what, const Scaling& s) {
        const double mb = static_cast<double>(s.bytes) / kMiB;
        t.add({what, fmt("%.0f", mb), fmt("%.4f", s.one_s), fmt("%.4f", s.two_s), fmt("%.2f", s.speedup()),
               fmt("%.1f", mb / 1024.0 / s.one_s)});
    };
    const int reps = std::max(c.reps, 9);  // milliseconds each: more runs, a steadier best
    try {
        add("page-cache read of " + l.raw.filename().string() + " (pread, 1 MiB pieces)", page_cache_read(l.raw, reps));
    } catch (const std::exception& e) {
        t.add({"page-cache read", "-", na(e.what()), "-", "-", "-"});
    }
    add("memory copy (memcpy, buffers faulted in)", memory_copy(std::size_t{256} << 20, reps));
    add("fresh memory (huge pages advised, written once, unmapped)", fresh_memory(std::size_t{128} << 20, reps));
    c.r.table(t);
}

void part_c(const Ctx& c, const Lung& l, double iso, const fs::path& splat_points, std::uint64_t splat_n) {
    c.r.section(fmt("(c) threads: %s, iso %g", l.label.c_str(), iso));
    c.r.note(fmt("Whole processes, --threads 2 vs --threads 1; ratio = speedup (1-thread seconds / 2-thread seconds). "
                 "The splat rows render %llu points (the synthetic sphere of (e)) at 1024x1024, quad kernel. Output = "
                 "byte comparison of the two outputs.",
                 static_cast<unsigned long long>(splat_n)));
    const std::string vol = shell_quote(l.nhdr.string()), iso_s = fmt(" --iso %g", iso);
    Table t{kProcessHeader, {}};
    const Timed i1 = c.run(c.m + " isosurface " + vol + iso_s + " -o " + c.out("c_t1.ply") + " --threads 1");
    const Timed i2 = c.run(c.m + " isosurface " + vol + iso_s + " -o " + c.out("c_t2.ply") + " --threads 2");
    add_row(t, "isosurface --threads 1", i1, "-", kNone, kNone, true);
    add_row(t, "isosurface --threads 2", i2, "--threads 1", i1.ok ? i1.seconds : kNone, 1.8,
            false, true, i1.ok && i2.ok ? compare_points(c.work / "c_t1.ply", c.work / "c_t2.ply") : std::string("-"));
    if (!c.o.quick) {  // --quick: the smoke test's few seconds
        const Timed p1 = c.run(c.m + " isosurface " + vol + iso_s + " -o " + c.out("c_t1.ply") + " --png " + c.out("c_t1.png") +
                               " --threads 1");
        const Timed p2 = c.run(c.m + " isosurface " + vol + iso_s + " -o " + c.out("c_t2.ply") + " --png " + c.out("c_t2.png") +
                               " --threads 2");
        add_row(t, "isosurface --png --threads 1", p1, "-", kNone, kNone, true);
        add_row(t, "isosurface --png --threads 2", p2, "--threads 1", p1.ok ? p1.seconds : kNone,
                1.8, false, true, p1.ok && p2.ok ? (read_file_bytes(c.work / "c_t1.png") == read_file_bytes(c.work / "c_t2.png") ? "SAME png" : "DIFFERENT png") : "-");
    }
    if (!splat_points.empty()) {
        const std::string in = shell_quote(splat_points.string());
        const Timed s1 = c.run(c.m + " splat " + in + " -o " + c.out("c_s1.png") + " --kernel quad --size 1024x1024 --threads 1");
        const Timed s2 = c.run(c.m + " splat " + in + " -o " + c.out("c_s2.png") + " --kernel quad --size 1024x1024 --threads 2");
        add_row(t, "splat --threads 1", s1, "-", kNone, kNone, true);
        add_row(t, "splat --threads 2", s2, "--threads 1", s1.ok ? s1.seconds : kNone, 1.8,
                false, true,
                s1.ok && s2.ok ? (read_file_bytes(c.work / "c_s1.png") == read_file_bytes(c.work / "c_s2.png") ? "SAME png" : "DIFFERENT png") : "-");
    }
    c.r.table(t);
    part_c_ceilings(c, l);
}

void part_d(const Ctx& c, const Lung& l, double iso) {
    c.r.section(fmt("(d) paradigm A vs C on the store: %s, iso %g", l.label.c_str(), iso));
    const fs::path mls = c.work / "d_lung.mls";
    std::error_code ec;
    fs::remove(mls, ec);  // made fresh each run: the binary measured decides its format
    Table t{kProcessHeader, {}};
    std::fprintf(stderr, "bench process: generate --all (paradigm A's sample store)\n");
    const Run g = run_sh(c.m + " generate " + shell_quote(l.mlb.string()) + " --all -o " + shell_quote(mls.string()), c.work / "stderr.txt");
    Timed gt;
    gt.ok = g.ok();
    gt.seconds = g.seconds;
    gt.maxrss_kib = g.maxrss_kib;
    gt.why = g.why(c.work.string());
    add_row(t, "generate STORE.mlb --all -o STORE.mls (once)", gt, "-", kNone, kNone, true);

    const std::string iso_s = fmt(" --iso %g", iso);
    const std::string tail = " | " + c.m + " project --threads 1 | " + c.m + " write -o ";
    const Timed C = c.run(c.m + " generate " + shell_quote(l.mlb.string()) + iso_s + " --threads 1" + tail + c.out("d_c.ply"));
    const Timed A = g.ok() ? c.run(c.m + " extract " + shell_quote(mls.string()) + iso_s + tail + c.out("d_a.ply")) : gt;
    const Timed I = c.run(c.m + " isosurface " + shell_quote(l.mlb.string()) + iso_s + " -o " + c.out("d_i.ply") +
                          " --threads 1 --stats");
    const Timed M = g.ok() ? c.run(c.m + " isosurface " + shell_quote(mls.string()) + iso_s + " -o " + c.out("d_m.ply") + " --threads 1")
                           : gt;
    // The floor of row A: the same sample stream saved to a file first (untimed), then only the
    // project and write processes that both pipelines pay; and a process that does nothing.
    const fs::path a_stream = c.work / "d_a.mls-stream";
    const bool saved = g.ok() && run_sh(c.m + " extract " + shell_quote(mls.string()) + iso_s + " > " + shell_quote(a_stream.string()),
                                        c.work / "stderr.txt").ok();
    const Timed F = saved ? c.run(c.m + " project --threads 1 < " + shell_quote(a_stream.string()) + " | " + c.m + " write -o " +
                                  c.out("d_f.ply"))
                          : gt;
    const Timed N = c.run(c.m + " --version > /dev/null");
    const double cs = C.ok ? C.seconds : kNone;
    add_row(t, "C: generate STORE.mlb | project | write", C, "-", kNone, kNone, true);
    add_row(t, "A: extract STORE.mls | project | write", A, "C pipeline", cs, 0.1, true, false,
            A.ok && C.ok ? compare_points(c.work / "d_a.ply", c.work / "d_c.ply") : std::string("-"));
    add_row(t, "  floor: project < A's stream | write", F, "C pipeline", cs, kNone, true);
    add_row(t, "  floor: meshless --version (one process)", N, "C pipeline", cs, kNone, true);
    add_row(t, "isosurface STORE.mlb (in-process C)", I, "C pipeline", cs, kNone, true);
    add_row(t, "isosurface STORE.mls (in-process A)", M, "C pipeline", cs, kNone, true, false,
            M.ok && C.ok ? compare_points(c.work / "d_m.ply", c.work / "d_c.ply") : std::string("-"));
    c.r.table(t);
    const std::uint64_t mls_b = file_bytes(mls), mlb_b = file_bytes(l.mlb);
    std::string active = "";
    if (I.ok)
        if (auto n = reported_active_cells(I.err)) {
            const auto& d = l.grid.dims;
            const double cells = static_cast<double>((d[0] - 1) * (d[1] - 1) * (d[2] - 1));
            active = fmt(" Active cells at iso %g: %lld = %.2f %% (isosurface --stats).", iso, *n, 100.0 * static_cast<double>(*n) / cells);
        }
    if (g.ok() && mlb_b > 0)
        c.r.note(fmt(".mls size / .mlb size = %s / %s = %.1fx (target <= 4: %s).%s", bytes_str(static_cast<double>(mls_b)).c_str(),
                     bytes_str(static_cast<double>(mlb_b)).c_str(), static_cast<double>(mls_b) / static_cast<double>(mlb_b),
                     static_cast<double>(mls_b) <= 4.0 * static_cast<double>(mlb_b) ? "PASS" : "FAIL", active.c_str()));
    else if (!active.empty())
        c.r.note(active.substr(1));
    c.r.note("Pipelines: project and generate with --threads 1; peak RSS is the largest process of the pipeline. "
             "Output = comparison with the C pipeline's PLY (sorted vertex records when the order differs). The floor rows "
             "bound row A from below: any paradigm (A) pipeline still runs the project and write processes on the same "
             "samples (the stream extract wrote, saved to a file beforehand), so row A's ratio cannot fall below the first "
             "floor's; paradigm (C) here reads only the bricks whose min/max span the isovalue (the brick index is itself a "
             "coarse span-space index), which is why A cannot win by Table 3.1's margin.");
    fs::remove(mls, ec);
    fs::remove(a_stream, ec);
}

void part_e(const Ctx& c, const std::vector<std::pair<std::uint64_t, fs::path>>& sets) {
    c.r.section("(e) splat throughput and peak memory: 1024x1024, quad kernel");
    c.r.note("Synthetic oriented points on a sphere (binary PLY, 32 B/point, spatially coherent rings, splat radius = mean "
             "spacing). `meshless splat PTS.ply -o out.png --kernel quad --size 1024x1024` as a whole process (read + "
             "render + PNG) with --threads 1 (without it when this build's splat has no --threads option: threads "
             "column 'default'); M points/s = points / seconds. Render only = `--turntable 1`'s reported ms/frame. "
             "Target: >= 20 M points/s per core (judged on the render-only rate when there is one), peak RSS "
             "independent of the point count.");
    Table t{{"points", "PLY MiB", "threads", "seconds", "M points/s", "peak RSS MiB", "RSS - PLY MiB", "render ms",
             "render M points/s", "target"},
            {}};
    for (const auto& [n, p] : sets) {
        const std::string in = shell_quote(p.string());
        const std::string base = c.m + " splat " + in + " --kernel quad --size 1024x1024";
        std::string threads = " --threads 1";
        Timed s = c.run(base + threads + " -o " + c.out("e.png"));
        if (!s.ok && s.why.find("--threads") != std::string::npos) {
            threads.clear();
            s = c.run(base + " -o " + c.out("e.png"));
        }
        const double ply_mib = static_cast<double>(file_bytes(p)) / kMiB;
        const std::string label = fmt("%.0e", static_cast<double>(n));
        if (!s.ok) {
            t.add({label, fmt("%.0f", ply_mib), threads.empty() ? "default" : "1", na(s.why), "-", "-", "-", "-", "-", "-"});
            continue;
        }
        const double rate = static_cast<double>(n) / s.seconds / 1e6;
        std::string rms = "n/a (no ms/frame reported)", rrate = "-";
        const Run tt = run_sh(base + threads + " -o " + c.out("e_tt.png") + " --turntable 1", c.work / "stderr.txt");
        std::optional<double> render_rate;
        if (!tt.ok()) rms = na(tt.why(c.work.string()));
        else if (auto ms = reported_ms_per_frame(tt.err)) {
            rms = fmt("%.1f", *ms);
            render_rate = static_cast<double>(n) / (*ms * 1e-3) / 1e6;
            rrate = fmt("%.3g", *render_rate);
        }
        const double best_rate = render_rate ? *render_rate : rate;
        t.add({label, fmt("%.0f", ply_mib), threads.empty() ? "default" : "1", secs(s.seconds), fmt("%.3g", rate),
               mib(s.maxrss_kib),
               fmt("%.0f", s.maxrss_kib / 1024.0 - ply_mib), rms, rrate,
               fmt(">= 20 M/s: %s", best_rate >= 20 ? "PASS" : "FAIL")});
    }
    c.r.table(t);
}

}  // namespace

void run_process(const BenchOptions& o, Report& r) {
    r.section("Whole processes: `meshless` as users run it");
    // inputs in `work` (kept when given), outputs of this run in its own folder inside it (always removed)
    const bool own_work = o.work_dir.empty();
    const fs::path work = own_work ? fs::temp_directory_path() / fmt("meshless-bench-process-%d", static_cast<int>(::getpid()))
                                   : fs::path(o.work_dir);
    fs::create_directories(work);
    const fs::path out = work / fmt("out-%d", static_cast<int>(::getpid()));
    fs::create_directories(out);
    auto clean_up = [&] {
        std::error_code ec;
        fs::remove_all(own_work ? work : out, ec);
    };
    const Run version = run_sh(shell_quote(o.meshless) + " --version", out / "stderr.txt", out / "version.txt");
    if (!version.ok()) {
        r.note("`" + o.meshless + " --version` failed (" + version.why() + "): process section skipped (give --meshless PATH).");
        clean_up();
        return;
    }
    const int reps = std::max(1, o.process_reps);
    r.note(fmt("Binary: %s (%s). Best of %d runs per row (--reps), wall clock of the whole process (fork to wait4), peak RSS = "
               "ru_maxrss of the shell running the command (its largest process), measured by a freshly started wrapper "
               "so that the bench's own memory does not count. Inputs in %s%s. The rows are timed on whatever else the machine runs: compare "
               "ratios within this run.",
               o.meshless.c_str(), first_line(version.out).c_str(), reps, work.c_str(),
               own_work ? " (temporary)" : " (kept; reused by later runs)"));
    Ctx c{o, r, out, reps, shell_quote(o.meshless)};

    // the splat point sets (no data needed)
    std::vector<std::pair<std::uint64_t, fs::path>> sets;
    std::vector<std::uint64_t> counts = o.quick ? std::vector<std::uint64_t>{10'000, 100'000}
                                                : std::vector<std::uint64_t>{1'000'000, 10'000'000};
    if (o.large && !o.quick) counts.push_back(100'000'000);
    try {
        for (auto n : counts) sets.emplace_back(n, sphere_points(work, n));
    } catch (const std::exception& e) {
        r.note(std::string("splat point sets could not be written: ") + e.what());
    }

    const Lung lung = make_lung(o, work, out, o.quick ? 1 : 2, r);
    if (!lung.ok) {
        r.note("Lung-sized CT unavailable: " + lung.why + ". Parts (a)-(d) skipped.");
    } else {
        r.note("Volume: " + lung.label + ", as " + lung.nhdr.filename().string() + " (detached NRRD header + raw) and " +
               lung.mlb.filename().string() + " (brick store).");
        part_a(c, lung, part_a_isovalues(o.quick ? 1 : 8));
        part_b(c, lung, 100.5);
        // the threads rows splat the largest set up to 10^7 points
        std::pair<std::uint64_t, fs::path> th{0, {}};
        for (const auto& s : sets)
            if (s.first <= 10'000'000) th = s;
        part_c(c, lung, 100.5, th.second, th.first);
        part_d(c, lung, 230.5);
    }
    if (!sets.empty()) part_e(c, sets);
    clean_up();
}

}  // namespace meshless::bench
