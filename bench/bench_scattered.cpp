// `meshless-bench scattered`: the numbers (dissertation chapter 5, sections 5.3-5.8, Table 5.1),
// measured by running `meshless isosurface POINTS` as a user would, one whole process per row, next to
// the peers users reach for today, run in the same invocation (bench/scattered_peers.py):
//   (a) accuracy against truth: analytic fields (sphere, gyroid, Marschner-Lobb; kernels/analytic_volumes)
//       sampled at 10^4 / 10^5 / 10^6 scattered points in three distributions (uniform, clustered = Gaussian
//       blobs at 100:1 density contrast, layered = dense in x, y and sparse in z; kernels/scattered_test_sets),
//       written once as PLY (double x y z value) into the work folder. Per set: `meshless isosurface SET.ply
//       --iso V --stats --threads 1 -o pts.ply` and the peers (SciPy griddata + flying edges, vtkDelaunay3D +
//       vtkContourFilter, vtkPointInterpolator (Gaussian, N closest) + flying edges), each a whole process
//       under a time limit (--peer-timeout; a peer that ran out of time is not run on the larger sizes of
//       the same field and distribution: "> T s"). The same measures on every output: mean and max distance
//       of the points (peers: mesh vertices) to the true isosurface (kernels/surface_coverage point_errors:
//       exact for the sphere, a Newton estimate for gyroid and ML), the mean normal error (degrees from -grad f, VTK's convention;
//       peers: area-weighted vertex normals of their triangles), and coverage: the fraction of a dense sampling
//       of the true isosurface (jittered grid spacing --quick 0.02 / 0.01, Newton-projected, samples within
//       2 / cbrt(N) of the cube's faces left out) within one splat radius of a meshless point; for the peers'
//       meshes, within the median meshless splat radius of that set of a point of the mesh's triangles (sampled
//       on a barycentric lattice of spacing <= a quarter of that radius).
//   (b) Table 5.1 rebuilt: bucky (20,000 random samples of the bucky volume upsampled x4 by `meshless synth`
//       to 125^3, the nearest to the paper's 128^3), silicium (17,532 points) and the head (the VTK headsq
//       quarter CT, 64x64x93: 203,359 and 345,452 points): LODs of `meshless hierarchy` when the binary has
//       that command, else uniform random samples of the same counts by `meshless sample` (the table says
//       which). The figures the paper lists are taken from `--stats` (binning level, empty cells,
//       regularisation points, stencils, tetrahedra, seeds, points, octree / field / regularisation /
//       isosurface seconds), next to the paper's.
//   (c) scaling: whole-process seconds for the 345 K head set and a 10^6-point head sample at 2 threads
//       (targets 10 s and 30 s on 2 cores), peak RSS at 10^5, 3x10^5 and 10^6 points (ru_maxrss of the
//       process, measured by a freshly executed wrapper, bench_process.cpp), 1 -> 2 threads speed-up with
//       identical point bytes, and 2 MPI ranks (`mpirun -np 2`) when mpirun is installed.
// A command that fails makes its cells "n/a (exit N: first line of stderr)"; the run goes on.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_common.hpp"
#include "formats/json.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/ply_points.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/point_set_writer.hpp"
#include "formats/field_file.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/field_isosurface_samples.hpp"
#include "kernels/scattered_test_sets.hpp"
#include "kernels/surface_coverage.hpp"

namespace meshless::bench {

namespace {

namespace fs = std::filesystem;

std::string first_line(const std::string& s) {
    std::string l = s.substr(0, s.find('\n'));
    if (l.size() > 90) l = l.substr(0, 90) + "...";
    for (char& c : l)
        if (static_cast<unsigned char>(c) < 0x20 || c == '|') c = ' ';
    return l;
}

// ---- whole processes with a time limit and their peak RSS -----------------------------------------

/// run_sh's result (bench/bench_common.hpp) with this bench's table-cell reason.
struct Proc : Run {
    std::string why(double limit) const {
        if (timed_out) return fmt("> %.0f s", limit);
        const std::string e = first_line(err.empty() ? out : err);
        return (code >= 128 ? fmt("n/a (signal %d", code - 128) : fmt("n/a (exit %d", code)) + (e.empty() ? ")" : ": " + e + ")");
    }
};

/// `/bin/sh -c cmd` (run_sh: stdin /dev/null, its own peak RSS) with stdout and stderr captured in
/// files under `dir`; after `limit` seconds its whole process group is killed.
Proc run_limited(const std::string& cmd, const fs::path& dir, double limit) {
    std::fprintf(stderr, "bench scattered: %s\n", cmd.c_str());
    Proc p;
    static_cast<Run&>(p) = run_sh(cmd, dir / "cmd.err", dir / "cmd.out", limit);
    // messages name the work folder (the parent of `dir`) as WORK/, to keep the table cells short
    const std::string wk = dir.parent_path().string() + "/";
    for (std::string* s : {&p.out, &p.err})
        for (std::size_t at; (at = s->find(wk)) != std::string::npos;) s->replace(at, wk.size(), "WORK/");
    return p;
}

/// Best of n runs (the fastest successful one, with its output); the first failure is returned.
Proc best_of(const std::string& cmd, int n, const fs::path& dir, double limit) {
    Proc best;
    for (int i = 0; i < n; ++i) {
        Proc p = run_limited(cmd, dir, limit);
        if (!p.ok()) return p;
        const long rss = std::max(best.maxrss_kib, p.maxrss_kib);
        if (i == 0 || p.seconds < best.seconds) best = std::move(p);
        best.maxrss_kib = rss;
    }
    return best;
}

// ---- --stats parsing -------------------------------------------------------------------------------

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool numch(char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == ','; }

/// The number written just after `label` (skipping ' ', ':', '=', as in "binning level 5", "field 0.12 s"),
/// or with a leading '<' in `label` the number just before the rest ("12 stencils (": "<stencils ("); the
/// first occurrence followed (preceded) by a number counts; thousands separators ',' dropped.
std::optional<double> stat_value(const std::string& text, std::string label) {
    const bool before = !label.empty() && label[0] == '<';
    if (before) label.erase(0, 1);
    const std::string l = lower(text), w = lower(label);
    for (std::size_t at = l.find(w); at != std::string::npos; at = l.find(w, at + 1)) {
        std::size_t b, e;
        if (!before) {
            b = at + w.size();
            while (b < l.size() && (l[b] == ' ' || l[b] == ':' || l[b] == '=')) ++b;
            e = b;
            while (e < l.size() && (numch(l[e]) || (e > b && (l[e] == 'e' || l[e] == '-' || l[e] == '+') && e + 1 < l.size() &&
                                                       std::isdigit(static_cast<unsigned char>(l[e + 1])))))
                ++e;
        } else {
            e = at;
            while (e > 0 && l[e - 1] == ' ') --e;
            b = e;
            while (b > 0 && numch(l[b - 1])) --b;
        }
        std::string d;
        for (std::size_t i = b; i < e; ++i)
            if (l[i] != ',') d += l[i];
        while (!d.empty() && d.back() == '.') d.pop_back();
        if (!d.empty() && std::isdigit(static_cast<unsigned char>(d[0]))) return std::strtod(d.c_str(), nullptr);
    }
    return std::nullopt;
}

/// The first of `labels` found in the --stats text.
std::optional<double> stat_any(const std::string& text, std::initializer_list<const char*> labels) {
    for (const char* l : labels)
        if (auto v = stat_value(text, l)) return v;
    return std::nullopt;
}

std::string stat_cell(const std::string& text, std::initializer_list<const char*> labels, const char* f = "%.0f") {
    const auto v = stat_any(text, labels);
    return v ? fmt(f, *v) : "?";
}

// ---- measuring outputs against the truth -----------------------------------------------------------

struct Measure {
    bool ok = false;
    std::string why;
    std::size_t elements = 0;  ///< points (meshless) or triangles (peers)
    double median_radius = 0;  ///< meshless points only
    PointErrors err;
    double coverage = 0;
    std::optional<double> field_coverage;  ///< meshless only: of the field's own isosurface
    std::string field_why;                 ///< why field_coverage is missing
    std::vector<Vec3> pos;                 ///< meshless only: the points and radii, kept for field_coverage
    std::vector<float> rad;
};

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

/// Distances of `pts` to the true isosurface: analytic_distance (exact for the sphere; for gyroid and ML a
/// Newton estimate, an upper bound that can be far off where the gradient is flat), tightened by the
/// distance to the nearest of `truth` (a dense sampling of the surface, also an upper bound) for points
/// whose estimate exceeds 2 x `spacing`: a hash grid searched to 0.25, beyond that all samples (at most
/// 2,000 such points; further ones keep the estimate). Sets mean_distance and max_distance of `e`.
void tighten_distances(AnalyticField f, double iso, const std::vector<Vec3>& pts, const std::vector<Vec3>& truth, double spacing,
                       PointErrors& e) {
    if (pts.empty()) return;
    constexpr double kCell = 0.05, kReach = 0.25;
    const int n = static_cast<int>(std::ceil(2.0 / kCell)) + 1;
    auto cell = [&](double x) { return std::clamp(static_cast<int>(std::floor((x + 1.0) / kCell)), 0, n - 1); };
    std::vector<std::uint32_t> start(static_cast<std::size_t>(n) * n * n + 1, 0), order(truth.size());
    auto key = [&](const Vec3& p) { return (static_cast<std::size_t>(cell(p.z)) * n + cell(p.y)) * n + cell(p.x); };
    for (const Vec3& t : truth) ++start[key(t) + 1];
    for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < truth.size(); ++i) order[fill[key(truth[i])]++] = static_cast<std::uint32_t>(i);
    }
    double sum = 0, mx = 0;
    std::size_t counted = 0, brute = 0;
    for (const Vec3& p : pts) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
        double d = analytic_distance(f, iso, p);
        if (f != AnalyticField::sphere && !truth.empty() && !(d <= 2 * spacing)) {
            double best2 = kReach * kReach;
            const int r = static_cast<int>(std::ceil(kReach / kCell));
            const int cx = cell(p.x), cy = cell(p.y), cz = cell(p.z);
            for (int z = std::max(0, cz - r); z <= std::min(n - 1, cz + r); ++z)
                for (int y = std::max(0, cy - r); y <= std::min(n - 1, cy + r); ++y)
                    for (int x = std::max(0, cx - r); x <= std::min(n - 1, cx + r); ++x) {
                        const std::size_t k = (static_cast<std::size_t>(z) * n + y) * n + x;
                        for (std::uint32_t a = start[k]; a < start[k + 1]; ++a) {
                            const Vec3 q = truth[order[a]] - p;
                            best2 = std::min(best2, dot(q, q));
                        }
                    }
            if (best2 < kReach * kReach) {
                d = std::min(d, std::sqrt(best2));
            } else if (brute < 2000) {
                ++brute;
                for (const Vec3& t : truth) best2 = std::min(best2, dot(t - p, t - p));
                d = std::min(d, std::sqrt(best2));
            }
        }
        if (!std::isfinite(d)) continue;
        sum += d;
        mx = std::max(mx, d);
        ++counted;
    }
    e.mean_distance = counted ? sum / static_cast<double>(counted) : 0;
    e.max_distance = mx;
}

Measure measure_points(const fs::path& ply, AnalyticField f, double iso, const std::vector<Vec3>& samples,
                       const std::vector<Vec3>& truth, double spacing) {
    Measure m;
    try {
        const PlyPoints pts = read_ply_points(ply.string());
        std::vector<Vec3> pos, nor;
        std::vector<float> rad;
        std::vector<double> r;
        for (const PointRecord& p : pts.points) {
            pos.push_back({p.pos[0], p.pos[1], p.pos[2]});
            nor.push_back({p.normal[0], p.normal[1], p.normal[2]});
            rad.push_back(p.radius);
            r.push_back(p.radius);
        }
        m.elements = pos.size();
        m.median_radius = median(r);
        m.err = point_errors(f, iso, pos, nor);
        tighten_distances(f, iso, pos, truth, spacing, m.err);
        m.coverage = surface_coverage(samples, pos, rad).fraction();
        m.pos = std::move(pos);
        m.rad = std::move(rad);
        m.ok = true;
    } catch (const std::exception& e) {
        m.why = "n/a (" + first_line(e.what()) + ")";
    }
    return m;
}

/// A peer's triangle mesh: vertex distances and area-weighted vertex normals against the truth;
/// coverage = surface samples within `tol` of a lattice point of the triangles (spacing <= tol / 4).
Measure measure_mesh(const fs::path& ply, AnalyticField f, double iso, const std::vector<Vec3>& samples, double tol,
                     const std::vector<Vec3>& truth, double spacing) {
    Measure m;
    try {
        const Mesh mesh = read_ply_mesh(ply.string());
        const std::size_t nv = mesh.vertex_count();
        std::vector<Vec3> pos(nv), nor(nv, Vec3{0, 0, 0});
        for (std::size_t v = 0; v < nv; ++v) pos[v] = {mesh.xyz[3 * v], mesh.xyz[3 * v + 1], mesh.xyz[3 * v + 2]};
        std::vector<Vec3> lattice;
        for (std::size_t t = 0; t + 2 < mesh.tri.size(); t += 3) {
            const Vec3 a = pos[mesh.tri[t]], b = pos[mesh.tri[t + 1]], c = pos[mesh.tri[t + 2]];
            const Vec3 n = cross(b - a, c - a);  // |n| = 2 x area: area weighting
            for (int k = 0; k < 3; ++k) nor[mesh.tri[t + static_cast<std::size_t>(k)]] = nor[mesh.tri[t + static_cast<std::size_t>(k)]] + n;
            const double e = std::max({norm(b - a), norm(c - b), norm(a - c)});
            const int s = std::max(1, static_cast<int>(std::ceil(e / (tol / 4))));
            for (int i = 0; i <= s; ++i)
                for (int j = 0; i + j <= s; ++j) {
                    const double u = static_cast<double>(i) / s, w = static_cast<double>(j) / s;
                    lattice.push_back(a * (1 - u - w) + b * u + c * w);
                }
        }
        m.elements = mesh.triangle_count();
        m.err = point_errors(f, iso, pos, nor);
        tighten_distances(f, iso, pos, truth, spacing, m.err);
        const std::vector<float> radii(lattice.size(), static_cast<float>(tol));
        m.coverage = surface_coverage(samples, lattice, radii).fraction();
        m.ok = true;
    } catch (const std::exception& e) {
        m.why = "n/a (" + first_line(e.what()) + ")";
    }
    return m;
}

// ---- the sections ---------------------------------------------------------------------------------

struct Ctx {
    Ctx(const BenchOptions& opt, Report& rep) : o(opt), r(rep) {}
    const BenchOptions& o;
    Report& r;
    fs::path work;       ///< inputs (kept with --work)
    fs::path out;        ///< outputs of this run
    std::string ml;      ///< quoted meshless binary
    bool peers = false;  ///< python3 with numpy, scipy, vtk
    double peer_limit = 120;
    double own_limit = 600;
    int peers_reused = 0;           ///< peer rows taken from WORK/peers (--reuse-peers)
    std::string peers_reused_from;  ///< the dates of those runs
};

constexpr double kFieldSurfaceSpacing = 0.02;  ///< 10^6 field evaluations over the cube per set

/// The completeness measure: the fraction of a dense sampling of the field's own isosurface
/// (kernels/field_isosurface_samples.hpp, jittered spacing `spacing`, the same margin as the truth's
/// samples) within one splat radius of the points measure_points kept in `m` (released here). The
/// field is the command's own, fitted again by `meshless fit SET` with the same --field (bit-identical).
void measure_field_coverage(const Ctx& c, const fs::path& set, double iso, double margin, double spacing, Measure& m) {
    const fs::path mlf = c.out / "field.mlf";
    fs::remove(mlf);
    const Proc fit = run_limited(c.ml + " fit " + shell_quote(set.string()) + " --zstd-level 0" +
                                     (c.o.scattered_field.empty() ? "" : " --field " + shell_quote(c.o.scattered_field)) + " -o " +
                                     shell_quote(mlf.string()),
                                 c.out, c.own_limit);
    if (!fit.ok()) {
        m.field_why = "fit: " + fit.why(c.own_limit);
        return;
    }
    try {
        const FieldFile ff = read_field_file(mlf.string());
        SurfaceSampling ss;
        ss.spacing = spacing;
        ss.margin = margin;
        const std::vector<Vec3> fs_samples = sample_field_isosurface(*ff.field, iso, Box3{{-1, -1, -1}, {1, 1, 1}}, ss);
        m.field_coverage = surface_coverage(fs_samples, m.pos, m.rad).fraction();
    } catch (const std::exception& e) {
        m.field_why = first_line(e.what());
    }
    fs::remove(mlf);
    m.pos = {};
    m.rad = {};
}

struct PeerDef {
    const char* method;
    const char* label;
    bool delaunay;  ///< a global Delaunay (the "faster than" target)
};
constexpr PeerDef kPeers[] = {
    {"griddata", "SciPy griddata linear + flying edges", true},
    {"delaunay", "vtkDelaunay3D + vtkContourFilter", true},
    {"interp", "vtkPointInterpolator Gaussian + flying edges", false},
};

std::string pct(double f) { return fmt("%.2f", 100 * f); }

/// Which sets get the peers: --quick the sphere's uniform set; --all-peers every set; else every set up to
/// 20,000 points, below 500,000 the sphere's three distributions and each field's uniform set, above that
/// the sphere's uniform set (a global Delaunay of 10^6 points takes minutes per run).
bool peers_here(const BenchOptions& o, AnalyticField f, ScatterDistribution d, std::size_t n) {
    const bool sphere = f == AnalyticField::sphere, uniform = d == ScatterDistribution::uniform;
    if (o.quick) return sphere && uniform;
    if (o.all_peers || n <= 20000) return true;
    if (n < 500000) return sphere || uniform;
    return sphere && uniform;
}

/// One peer run, or with --reuse-peers its record from an earlier run in WORK/peers (kept there after every
/// run: the mesh and a small text record of exit code, time, limit, stdout and the first line of stderr).
/// A cached time-out under a smaller limit than this run's is run again. `mesh` receives the mesh's path.
Proc run_peer(Ctx& c, const PeerDef& p, const fs::path& set, const std::string& name, double iso, int grid, fs::path& mesh) {
    const fs::path dir = c.work / "peers";
    std::error_code ec;
    fs::create_directories(dir, ec);
    const std::string key = fmt("%s-%s-g%d", name.c_str(), p.method, grid);
    mesh = dir / (key + ".ply");
    const fs::path rec = dir / (key + ".txt");
    if (c.o.reuse_peers && fs::exists(rec)) {
        std::ifstream in(rec);
        Proc q;
        double limit = 0;
        int timed = 0;
        std::string when, line;
        if (in >> q.code >> timed >> q.seconds >> limit >> q.maxrss_kib && std::getline(in, line) && std::getline(in, when) &&
            std::getline(in, q.out) && std::getline(in, q.err)) {
            q.timed_out = timed != 0;
            if (!(q.timed_out && limit < c.peer_limit) && (!q.ok() || fs::exists(mesh))) {
                ++c.peers_reused;
                if (c.peers_reused_from.find(when) == std::string::npos)
                    c.peers_reused_from += (c.peers_reused_from.empty() ? "" : ", ") + when;
                return q;
            }
        }
    }
    fs::remove(mesh, ec);
    const Proc pr = run_limited(shell_quote(c.o.python) + " " + shell_quote((fs::path(c.o.bench_dir) / "scattered_peers.py").string()) +
                                    " --method " + p.method + " --input " + shell_quote(set.string()) +
                                    fmt(" --iso %.17g --grid %d --out ", iso, grid) + shell_quote(mesh.string()),
                                c.out, c.peer_limit);
    if (std::ofstream out(rec); out)
        out << pr.code << ' ' << (pr.timed_out ? 1 : 0) << ' ' << fmt("%.6f", pr.seconds) << ' ' << c.peer_limit << ' ' << pr.maxrss_kib
            << '\n' << now_string() << '\n' << pr.out.substr(0, pr.out.find('\n')) << '\n' << first_line(pr.err) << '\n';
    return pr;
}

void part_a(Ctx& c) {
    const BenchOptions& o = c.o;
    const std::vector<std::size_t> sizes = !o.scattered_sizes.empty() ? parse_scattered_sizes(o.scattered_sizes)
                                           : o.quick ? std::vector<std::size_t>{3000}
                                                     : std::vector<std::size_t>{10000, 100000, 1000000};
    std::vector<AnalyticField> fields = {AnalyticField::sphere, AnalyticField::gyroid, AnalyticField::marschner_lobb};
    if (o.quick) fields = {AnalyticField::sphere, AnalyticField::gyroid};
    std::vector<ScatterDistribution> dists = {ScatterDistribution::uniform, ScatterDistribution::clustered,
                                              ScatterDistribution::layered};
    if (!o.scattered_fields.empty()) {
        fields.clear();
        for (const std::string& w : split_list(o.scattered_fields)) fields.push_back(*parse_analytic_field(w));
    }
    if (!o.scattered_distributions.empty()) {
        dists.clear();
        for (const std::string& w : split_list(o.scattered_distributions)) dists.push_back(*parse_scatter_distribution(w));
    }
    const double spacing = o.quick ? 0.02 : 0.01;
    c.r.section("(a) Accuracy against truth and the peers: analytic fields at scattered points");
    c.r.note(fmt("meshless: `meshless isosurface SET.ply --iso V --stats --threads 1%s -o pts.ply` (one thread: the peers are "
                 "single-threaded Python/VTK). Peers (bench/scattered_peers.py, %s; %s): SciPy griddata linear (Qhull) onto an "
                 "n^3 grid (n = clamp(round(cbrt(N)), 16, 128)) over the points' bounding box + vtkFlyingEdges3D; vtkDelaunay3D "
                 "+ vtkContourFilter; vtkPointInterpolator (Gaussian kernel, 8 closest) onto the same grid + vtkFlyingEdges3D. "
                 "Seconds: whole process, wall clock (peers: interpreter start and imports included; their own compute "
                 "time after the slash), limit %.0f s per peer run (\"> T s\": stopped; not run on larger sizes of that set). "
                 "Distances to the true isosurface in world units (cube [-1,1]^3), mean / max over the points (peers: "
                 "mesh vertices; sphere exact, gyroid and ML the smaller of a Newton estimate and the distance to the "
                 "nearest true-surface sample, both upper bounds); normal error mean, degrees from -grad f, VTK's convention (peers: area-weighted vertex normals of their triangles' winding); "
                 "coverage: true-surface samples (jittered grid spacing %.2g, Newton-projected, 2/cbrt(N) from the cube's "
                 "faces left out) within one splat radius of a meshless point (target >= 99%%), for a peer's mesh within the "
                 "median meshless splat radius of the set of its triangles; field-surface coverage (the completeness "
                 "measure, meshless only): samples of the field's own isosurface (the command's field fitted again by "
                 "`meshless fit`, jittered spacing 0.02, Newton-projected onto the field, the same margin) within one splat "
                 "radius (target >= 99%%): where the truth's coverage falls short but this does not, the field, not the "
                 "extraction, misses the truth. Ratios: peer / meshless (time > 1: meshless "
                 "faster; mean distance > 1: meshless more accurate). The machine is shared with other builds and "
                 "benchmarks: compare within this run.",
                 o.scattered_field.empty() ? "" : (" --field " + o.scattered_field).c_str(),
                 c.peers ? "python3-scipy, python3-vtk9" : o.no_peers ? "not run: --no-peers" : "not run: numpy/scipy/vtk not importable",
                 o.quick ? "on the sphere's uniform set" : o.all_peers ? "on every set"
                         : "on every set up to 20,000 points, below 500,000 on the sphere's three distributions and each "
                           "field's uniform set, above on the sphere's uniform set (--all-peers: every set)",
                 c.peer_limit, spacing));
    Table t;
    t.header = {"set", "N", "method", "points / triangles", "seconds", "mean dist", "max dist", "normal err deg",
                "coverage %", "time ratio", "mean dist ratio", "field-surface coverage %"};
    struct Tally {
        int sets = 0, compared = 0, more_accurate = 0, faster_than_delaunay = 0, delaunay_rows = 0, covered = 0, field_covered = 0;
    };
    std::map<std::size_t, Tally> tally;
    std::map<std::string, bool> peer_gave_up;  // "method|field|dist"
    const fs::path sets = c.work / "sets";
    fs::create_directories(sets);
    for (AnalyticField f : fields) {
        const double iso = default_iso(f);
        const std::vector<Vec3> all_samples = [&] {
            SurfaceSampling ss;
            ss.spacing = spacing;
            return sample_isosurface(f, iso, Box3{{-1, -1, -1}, {1, 1, 1}}, ss);
        }();
        for (ScatterDistribution d : dists)
            for (std::size_t n : sizes) {
                const ScatteredSetSpec spec{f, d, n, 1};
                const std::string name = scattered_set_name(spec);
                const fs::path set = sets / (name + ".ply");
                if (!fs::exists(set))
                    write_point_set_ply(set.string(), make_scattered_set(spec),
                                        {"meshless-bench scattered: " + name + ", seed 1 (kernels/scattered_test_sets)"});
                const double margin = 2.0 / std::cbrt(static_cast<double>(n));
                std::vector<Vec3> samples;
                for (const Vec3& s : all_samples)
                    if (std::abs(s.x) <= 1 - margin && std::abs(s.y) <= 1 - margin && std::abs(s.z) <= 1 - margin) samples.push_back(s);
                const std::string setname = fmt("%s %s", to_string(f), to_string(d));
                const std::string nstr = fmt("%zu", n);
                // meshless
                const fs::path pts = c.out / "pts.ply";
                fs::remove(pts);
                const Proc own = run_limited(c.ml + " isosurface " + shell_quote(set.string()) + fmt(" --iso %.17g --stats --threads 1", iso) +
                                                 (o.scattered_field.empty() ? "" : " --field " + shell_quote(o.scattered_field)) +
                                                 " -o " + shell_quote(pts.string()),
                                             c.out, c.own_limit);
                Measure mine;
                if (own.ok()) {
                    mine = measure_points(pts, f, iso, samples, all_samples, spacing);
                    if (mine.ok) measure_field_coverage(c, set, iso, margin, kFieldSurfaceSpacing, mine);
                } else {
                    mine.why = own.why(c.own_limit);
                }
                if (mine.ok) {
                    t.add({setname, nstr, "meshless", fmt("%zu", mine.elements), fmt("%.2f", own.seconds), fmt("%.2e", mine.err.mean_distance),
                           fmt("%.2e", mine.err.max_distance), fmt("%.2f", mine.err.mean_normal_deg),
                           pct(mine.coverage) + (mine.coverage >= 0.99 ? "" : " (< 99)"), "1", "1",
                           mine.field_coverage ? pct(*mine.field_coverage) + (*mine.field_coverage >= 0.99 ? "" : " (< 99)")
                                               : "n/a (" + mine.field_why + ")"});
                } else {
                    std::vector<std::string> row{setname, nstr, "meshless", mine.why};
                    row.resize(t.header.size(), "-");
                    t.add(row);
                }
                Tally& ty = tally[n];
                ++ty.sets;
                if (mine.ok && mine.coverage >= 0.99) ++ty.covered;
                if (mine.field_coverage && *mine.field_coverage >= 0.99) ++ty.field_covered;
                bool best = mine.ok;
                const double tol = mine.ok && mine.median_radius > 0 ? mine.median_radius : 2.0 / std::cbrt(static_cast<double>(n));
                if (!c.peers || !peers_here(o, f, d, n)) continue;
                ++ty.compared;
                const int grid = static_cast<int>(std::clamp(std::lround(std::cbrt(static_cast<double>(n))), 16L, 128L));
                for (const PeerDef& p : kPeers) {
                    std::vector<std::string> row{setname, nstr, p.label};
                    const std::string key = std::string(p.method) + "|" + to_string(f) + "|" + to_string(d);
                    if (peer_gave_up[key]) {
                        row.push_back("> " + fmt("%.0f", c.peer_limit) + " s at a smaller N: not run");
                        row.resize(t.header.size(), "-");
                        t.add(row);
                        if (p.delaunay && mine.ok) ++ty.delaunay_rows, ++ty.faster_than_delaunay;
                        continue;
                    }
                    fs::path mesh;
                    const Proc pr = run_peer(c, p, set, name, iso, grid, mesh);
                    if (!pr.ok()) {
                        if (pr.timed_out) peer_gave_up[key] = true;
                        row.push_back("-");
                        row.push_back(pr.why(c.peer_limit));
                        row.resize(t.header.size(), "-");
                        if (pr.timed_out && mine.ok) row[9] = fmt("> %.1f", c.peer_limit / own.seconds);
                        t.add(row);
                        if (p.delaunay && mine.ok) {
                            ++ty.delaunay_rows;
                            if (pr.timed_out) ++ty.faster_than_delaunay;
                        }
                        continue;
                    }
                    double compute = -1;
                    try {
                        const Json j = parse_json(pr.out, "scattered_peers.py output");
                        compute = 0;
                        for (const char* k : {"interpolate_seconds", "contour_seconds"})
                            if (const Json* x = j.find(k); x && x->is_number()) compute += x->num;
                    } catch (const std::exception&) {
                        compute = -1;
                    }
                    const Measure pm = measure_mesh(mesh, f, iso, samples, tol, all_samples, spacing);
                    if (!pm.ok) {
                        row.push_back(pm.why);
                        row.resize(t.header.size(), "-");
                        t.add(row);
                        continue;
                    }
                    row.push_back(fmt("%zu", pm.elements));
                    row.push_back(fmt("%.2f", pr.seconds) + (compute >= 0 ? fmt(" / %.2f", compute) : ""));
                    row.push_back(fmt("%.2e", pm.err.mean_distance));
                    row.push_back(fmt("%.2e", pm.err.max_distance));
                    row.push_back(fmt("%.2f", pm.err.mean_normal_deg));
                    row.push_back(pct(pm.coverage));
                    if (mine.ok) {
                        row.push_back(fmt("%.2fx", pr.seconds / own.seconds));
                        row.push_back(mine.err.mean_distance > 0 ? fmt("%.2fx", pm.err.mean_distance / mine.err.mean_distance) : "-");
                        if (!(mine.err.mean_distance < pm.err.mean_distance)) best = false;
                        if (p.delaunay) {
                            ++ty.delaunay_rows;
                            if (own.seconds < pr.seconds) ++ty.faster_than_delaunay;
                        }
                    } else {
                        row.push_back("-");
                        row.push_back("-");
                    }
                    row.resize(t.header.size(), "-");
                    t.add(row);
                }
                if (best) ++ty.more_accurate;
            }
    }
    c.r.table(t);
    if (c.peers_reused)
        c.r.note(fmt("--reuse-peers: %d peer rows were taken from earlier runs of this bench on this machine (%s), kept in ",
                     c.peers_reused, c.peers_reused_from.c_str()) + (c.work / "peers").string() +
                 "; their times were not measured in this run.");
    Table s;
    s.header = {"N", "sets", "meshless coverage >= 99%", "of the field's own isosurface >= 99%",
                "meshless mean distance below every peer's (sets with peers)", "meshless faster than the Delaunay peers (runs)"};
    for (const auto& [n, ty] : tally)
        s.add({fmt("%zu", n), fmt("%d", ty.sets), fmt("%d of %d", ty.covered, ty.sets), fmt("%d of %d", ty.field_covered, ty.sets),
               ty.compared ? fmt("%d of %d", ty.more_accurate, ty.compared) : "- (no peers)",
               ty.delaunay_rows ? fmt("%d of %d", ty.faster_than_delaunay, ty.delaunay_rows) : "- (no peers)"});
    c.r.note("Summary against the goals: more accurate than every peer at every size, faster end to end than the "
             "Delaunay-based peers (griddata, vtkDelaunay3D) from 10^5 points up (a peer stopped by the time limit counts "
             "as slower)." + std::string(o.quick ? " (--quick: peers on the sphere's uniform set only.)" : ""));
    c.r.table(s);
}

// ---- (b) Table 5.1 ---------------------------------------------------------------------------------

struct Set51 {
    Set51() = default;
    Set51(std::string l, std::string pp, std::string pr, std::string pe, std::string pt)
        : label(std::move(l)), paper_points(std::move(pp)), paper_rbfs(std::move(pr)), paper_empty(std::move(pe)), paper_times(std::move(pt)) {}
    std::string label, paper_points, paper_rbfs, paper_empty, paper_times;
    fs::path ply;
    std::string how, why;
    double iso = 0;
    std::size_t count = 0;
};

bool binary_has_command(const Ctx& c, const std::string& cmd) {
    const Proc p = run_limited(c.ml + " " + cmd + " --help", c.out, 30);
    return p.ok();
}

/// `meshless sample VOL --count N` (cached in the work folder).
std::size_t read_point_set_count(const fs::path& ply) {
    return read_point_set(ply.string(), PointSetOptions{}).size();
}

void sample_set(Ctx& c, Set51& s, const std::string& vol, const std::string& vol_opts, std::size_t n, std::uint64_t seed) {
    s.count = n;
    s.ply = c.work / fmt("%s-%zu.ply", s.label.c_str(), n);
    if (fs::exists(s.ply)) return;
    const Proc p = run_limited(c.ml + " sample " + shell_quote(vol) + vol_opts + fmt(" --count %zu --seed %llu -o ", n,
                                                                                     static_cast<unsigned long long>(seed)) +
                                   shell_quote(s.ply.string()),
                               c.out, c.own_limit);
    if (!p.ok()) s.why = p.why(c.own_limit);
}

/// A level of detail of `meshless hierarchy` (chapter 6): a tree of n - 1 splits (n clusters when
/// no split is skipped) and its finest LOD (`lod --error 0`), cached in the work folder. False (with
/// s.why) when a command fails or runs out of time; the caller falls back to random samples.
bool lod_set(Ctx& c, Set51& s, const std::string& vol, const std::string& vol_opts, std::size_t n) {
    const fs::path tree = c.work / fmt("%s-%zu.mlh", s.label.c_str(), n);
    s.ply = c.work / fmt("%s-lod-%zu.ply", s.label.c_str(), n);
    if (!fs::exists(s.ply)) {
        if (!fs::exists(tree)) {
            const Proc h = run_limited(c.ml + " hierarchy " + shell_quote(vol) + vol_opts + fmt(" --max-splits %zu --threads 2 -o ", n - 1) +
                                           shell_quote(tree.string()),
                                       c.out, c.own_limit);
            if (!h.ok()) {
                s.why = "hierarchy: " + h.why(c.own_limit);
                return false;
            }
        }
        const Proc l = run_limited(c.ml + " lod " + shell_quote(tree.string()) + " --error 0 -o " + shell_quote(s.ply.string()), c.out,
                                   c.own_limit);
        if (!l.ok()) {
            s.why = "lod: " + l.why(c.own_limit);
            return false;
        }
    }
    try {
        s.count = read_point_set_count(s.ply);
    } catch (const std::exception& e) {
        s.why = "n/a (" + first_line(e.what()) + ")";
        return false;
    }
    s.how = fmt("the finest level of detail of `meshless hierarchy --max-splits %zu` (%zu points)", n - 1, s.count);
    return true;
}

/// Random samples when the binary has no hierarchy command, or when it failed (said in s.how).
void lod_or_sample(Ctx& c, Set51& s, bool hierarchy, const std::string& vol, const std::string& vol_opts, std::size_t n,
                   std::uint64_t seed, const std::string& what) {
    std::string failed;
    if (hierarchy) {
        if (lod_set(c, s, vol, vol_opts, n)) return;
        failed = s.why;
        s.why.clear();
    }
    s.how = fmt("%zu uniform random samples of %s (%s)", n, what.c_str(),
                hierarchy ? ("`meshless hierarchy` failed: " + failed).c_str() : "no `meshless hierarchy` in this binary");
    sample_set(c, s, vol, vol_opts, n, seed);
}

void part_b(Ctx& c) {
    const BenchOptions& o = c.o;
    c.r.section("(b) Table 5.1 rebuilt: silicium, bucky, the head at two levels of detail");
    const fs::path D(o.data_dir);
    const bool hierarchy = binary_has_command(c, "hierarchy");
    std::vector<Set51> sets;
    const std::string raw_u8 = " --type uint8";
    {  // bucky: 20,000 random samples of the bucky volume upsampled to ~128^3
        Set51 s{"bucky", "20,000", "4,096", "31", "0.2 / 3.1 / 0.1 / 69.2 s"};
        s.iso = 128.5;
        const std::string vol = (D / "bucky/Bucky_32x32x32_uint8.raw").string();
        if (!fs::exists(vol)) {
            s.why = "n/a (bucky/Bucky_32x32x32_uint8.raw not in the data folder)";
        } else if (o.quick) {
            s.how = "2,000 random samples of the 32^3 volume (--quick)";
            sample_set(c, s, vol, " --dims 32,32,32" + raw_u8, 2000, 1);
        } else {
            const fs::path big = c.work / "bucky125.mlb";
            if (!fs::exists(big)) {
                const Proc p = run_limited(c.ml + " synth --upsample 4 " + shell_quote(vol) + " --dims 32,32,32" + raw_u8 + " -o " +
                                               shell_quote(big.string()),
                                           c.out, c.own_limit);
                if (!p.ok()) s.why = "synth: " + p.why(c.own_limit);
            }
            if (s.why.empty()) {
                s.how = "20,000 uniform random samples of bucky upsampled x4 (synth, 125^3)";
                sample_set(c, s, big.string(), "", 20000, 1);
            }
        }
        sets.push_back(s);
    }
    {
        Set51 s{"silicium", "17,532", "4,180", "2,519", "0.1 / 3.2 / 0.1 / 176.3 s"};
        s.iso = 128.5;
        const std::string vol = (D / "silicium/silicium_98x34x34_uint8.raw").string();
        if (!fs::exists(vol)) {
            s.why = "n/a (silicium not in the data folder)";
        } else {
            const std::size_t n = o.quick ? 2000 : 17532;
            // the file's name gives its dims and type (`hierarchy` reads volumes as point sets, without --dims)
            lod_or_sample(c, s, hierarchy && !o.quick, vol, "", n, 2, "the silicium volume");
        }
        sets.push_back(s);
    }
    if (!o.quick) {
        for (const auto& [label, n, paper] : {std::tuple<const char*, std::size_t, std::array<const char*, 4>>{
                                                  "head-LowRes", 203359, {"203,359", "66,961", "199,206", "1.4 / 26.9 / 4.9 / 364.2 s"}},
                                              std::tuple<const char*, std::size_t, std::array<const char*, 4>>{
                                                  "head-HighRes", 345452, {"345,452", "92,022", "1,758,408", "1.9 / 48.8 / 45.5 / 375.1 s"}}}) {
            Set51 s{label, paper[0], paper[1], paper[2], paper[3]};
            s.iso = 500;
            const std::string vol = (D / "vtk_headsq/quarter.nhdr").string();
            if (!fs::exists(vol)) {
                s.why = "n/a (vtk_headsq/quarter.nhdr not in the data folder)";
            } else {
                lod_or_sample(c, s, hierarchy, vol, "", n, 3, "the headsq quarter CT (64x64x93)");
            }
            sets.push_back(s);
        }
    }
    c.r.note("`meshless isosurface SET.ply --iso V --stats --threads 2 -o pts.ply`, best of " + fmt("%d", o.process_reps) +
             ", figures from --stats (\"?\": not printed by this binary). Paper: eleven 2.8-3.2 GHz PCs over MPI; its times "
             "are octree / local RBF construction / regularisation / isosurface generation. Isovalues: bucky and silicium "
             "128.5, head 500 (skin). Sets:");
    for (const Set51& s : sets)
        if (s.why.empty()) c.r.note("- " + s.label + ": " + s.how + (s.ply.empty() ? "" : " (" + s.ply.filename().string() + ")"));
    Table t;
    t.header = {"set", "points (paper)", "local RBFs (paper)", "empty cells (paper)", "times (paper)", "points", "binning level",
                "empty cells", "regularisation points", "stencils", "tetrahedra", "seeds", "output points", "octree s", "field s",
                "regularisation s", "isosurface s", "Delaunay failures", "whole process s", "peak RSS MiB"};
    for (const Set51& s : sets) {
        std::vector<std::string> row{s.label, s.paper_points, s.paper_rbfs, s.paper_empty, s.paper_times};
        if (!s.why.empty()) {
            row.push_back(s.why);
            row.resize(t.header.size(), "-");
            t.add(row);
            continue;
        }
        row.push_back(fmt("%zu", s.count));
        const fs::path pts = c.out / "t51.ply";
        const Proc p = best_of(c.ml + " isosurface " + shell_quote(s.ply.string()) + fmt(" --iso %.17g --stats --threads 2", s.iso) +
                                   (o.scattered_field.empty() ? "" : " --field " + shell_quote(o.scattered_field)) + " -o " +
                                   shell_quote(pts.string()),
                               o.process_reps, c.out, c.own_limit);
        if (!p.ok()) {
            row.push_back(p.why(c.own_limit));
            row.resize(t.header.size(), "-");
            t.add(row);
            continue;
        }
        const std::string& st = p.err;
        // the lines of `meshless isosurface POINTS --stats` (cli/scattered_isosurface.cpp)
        row.push_back(stat_cell(st, {"binning level"}));
        row.push_back(stat_cell(st, {"<empty (", "<empty cells"}));
        row.push_back(stat_cell(st, {"<regularisation points"}));
        row.push_back(stat_cell(st, {"<stencils ("}));
        row.push_back(stat_cell(st, {"<tets (", "<tetrahedra"}));
        row.push_back(stat_cell(st, {"<seeds (n", "<seeds"}));
        row.push_back(stat_cell(st, {"<points; time"}));
        row.push_back(stat_cell(st, {"octree + binning", "octree"}, "%.3f"));
        row.push_back(stat_cell(st, {"field"}, "%.3f"));
        row.push_back(stat_cell(st, {"regularisation"}, "%.3f"));
        row.push_back(stat_cell(st, {"output)"}, "%.3f"));
        row.push_back(stat_cell(st, {"<delaunay failures"}));
        row.push_back(fmt("%.2f", p.seconds));
        row.push_back(fmt("%.0f", p.maxrss_kib / 1024.0));
        t.add(row);
    }
    c.r.table(t);
}

// ---- (c) scaling ----------------------------------------------------------------------------------

std::string body_after_header(const fs::path& p) {
    const std::string s = read_file_bytes(p);
    const std::size_t h = s.find("end_header\n");
    return h == std::string::npos ? s : s.substr(h + 11);
}

void part_c(Ctx& c) {
    const BenchOptions& o = c.o;
    c.r.section("(c) Scaling: whole-process time, peak memory, threads, MPI ranks");
    const fs::path D(o.data_dir);
    const std::string vol = (D / "vtk_headsq/quarter.nhdr").string();
    if (!fs::exists(vol)) {
        c.r.note("vtk_headsq/quarter.nhdr not in the data folder: part (c) skipped.");
        return;
    }
    const std::vector<std::size_t> counts = o.quick ? std::vector<std::size_t>{2000, 6000}
                                                    : std::vector<std::size_t>{100000, 345452, 1000000};
    c.r.note(fmt("Uniform random samples of the headsq quarter CT (`meshless sample`, seed 3), iso 500; `meshless isosurface SET.ply "
                 "--iso 500 --threads T -o pts.ply`, best of %d, wall clock of the whole process; peak RSS = ru_maxrss of its "
                 "largest process (freshly executed wrapper). Targets: 345 K points <= 10 s and 10^6 <= 30 s on 2 "
                 "cores; memory growing with the point count; 1 -> 2 threads >= 1.8x with identical point bytes. Machine: %s, "
                 "shared with other builds and benchmarks while this ran.",
                 o.process_reps, machine_description().c_str()));
    Table t;
    t.header = {"points", "1 thread s", "2 threads s", "speed-up", "same bytes", "target", "peak RSS MiB (2 threads)",
                "RSS bytes / input point", "output points"};
    bool mpi_done = false;
    std::string mpi_row_set;
    fs::path mpi_ply;
    Proc mpi_base;
    for (std::size_t n : counts) {
        Set51 s;
        s.label = "head";
        sample_set(c, s, vol, "", n, 3);
        std::vector<std::string> row{fmt("%zu", n)};
        if (!s.why.empty()) {
            row.push_back(s.why);
            row.resize(t.header.size(), "-");
            t.add(row);
            continue;
        }
        const fs::path o1 = c.out / "s1.ply", o2 = c.out / "s2.ply";
        const auto cmd = [&](int th, const fs::path& out) {
            return c.ml + " isosurface " + shell_quote(s.ply.string()) + fmt(" --iso 500 --threads %d", th) +
                   (o.scattered_field.empty() ? "" : " --field " + shell_quote(o.scattered_field)) + " -o " + shell_quote(out.string());
        };
        const Proc p1 = best_of(cmd(1, o1), o.process_reps, c.out, c.own_limit);
        const Proc p2 = best_of(cmd(2, o2), o.process_reps, c.out, c.own_limit);
        row.push_back(p1.ok() ? fmt("%.2f", p1.seconds) : p1.why(c.own_limit));
        row.push_back(p2.ok() ? fmt("%.2f", p2.seconds) : p2.why(c.own_limit));
        row.push_back(p1.ok() && p2.ok() ? fmt("%.2fx", p1.seconds / p2.seconds) : "-");
        row.push_back(p1.ok() && p2.ok() ? (body_after_header(o1) == body_after_header(o2) ? "SAME" : "DIFFERENT") : "-");
        const double limit = n >= 1000000 ? 30 : n >= 345000 ? 10 : 0;
        row.push_back(limit > 0 ? (p2.ok() ? fmt("<= %.0f s: %s", limit, p2.seconds <= limit ? "PASS" : "FAIL") : fmt("<= %.0f s", limit)) : "-");
        row.push_back(p2.ok() ? fmt("%.0f", p2.maxrss_kib / 1024.0) : "-");
        row.push_back(p2.ok() ? fmt("%.0f", p2.maxrss_kib * 1024.0 / static_cast<double>(n)) : "-");
        std::size_t npts = 0;
        if (p2.ok()) try {
                npts = read_ply_points(o2.string()).points.size();
            } catch (const std::exception&) {
            }
        row.push_back(p2.ok() ? fmt("%zu", npts) : "-");
        t.add(row);
        if (!mpi_done && p1.ok() && (o.quick || n >= 345000)) {
            mpi_done = true;
            mpi_row_set = s.ply.string();
            mpi_ply = c.out / "mpi_base.ply";  // o1 is overwritten by the next size's run
            fs::copy_file(o1, mpi_ply, fs::copy_options::overwrite_existing);
            mpi_base = p1;
        }
    }
    c.r.table(t);
    // MPI: 2 ranks of one thread each against 1 process of one thread
    if (o.quick) return;
    const Proc which = run_limited("command -v mpirun", c.out, 10);
    if (!which.ok()) {
        c.r.note("MPI: mpirun not found: no MPI row.");
        return;
    }
    if (!mpi_done) {
        c.r.note("MPI: no single-process baseline succeeded: no MPI row.");
        return;
    }
    const fs::path om = c.out / "mpi.ply";
    const Proc pm = best_of("mpirun -np 2 --allow-run-as-root --oversubscribe " + c.ml + " isosurface " + shell_quote(mpi_row_set) +
                                " --iso 500 --threads 1" +
                                (o.scattered_field.empty() ? "" : " --field " + shell_quote(o.scattered_field)) + " -o " +
                                shell_quote(om.string()),
                            o.process_reps, c.out, c.own_limit);
    Table m;
    m.header = {"set", "1 process 1 thread s", "2 ranks s", "speed-up", "same bytes", "peak RSS MiB (largest process)"};
    std::vector<std::string> row{fs::path(mpi_row_set).filename().string(), fmt("%.2f", mpi_base.seconds)};
    if (!pm.ok()) {
        row.push_back(pm.why(c.own_limit));
        row.resize(m.header.size(), "-");
    } else {
        row.push_back(fmt("%.2f", pm.seconds));
        row.push_back(fmt("%.2fx", mpi_base.seconds / pm.seconds));
        row.push_back(body_after_header(mpi_ply) == body_after_header(om) ? "SAME" : "DIFFERENT");
        row.push_back(fmt("%.0f", pm.maxrss_kib / 1024.0));
    }
    c.r.note("`mpirun -np 2 --allow-run-as-root --oversubscribe meshless isosurface SET.ply --iso 500 --threads 1 -o pts.ply` "
             "against one process of one thread; RSS: ru_maxrss of the largest process of the job (rank 0 or 1, or mpirun).");
    m.add(row);
    c.r.table(m);
}

}  // namespace

std::vector<std::string> split_list(const std::string& s) {
    std::vector<std::string> v;
    std::size_t at = 0;
    while (at <= s.size()) {
        const std::size_t c = s.find(',', at);
        v.push_back(s.substr(at, c == std::string::npos ? std::string::npos : c - at));
        if (c == std::string::npos) break;
        at = c + 1;
    }
    return v;
}

void check_scattered_lists(const BenchOptions& o) {
    if (!o.scattered_fields.empty())
        for (const std::string& w : split_list(o.scattered_fields))
            if (!parse_analytic_field(w)) throw std::invalid_argument("--fields: expected sphere, torus, gyroid or ml (got '" + w + "')");
    if (!o.scattered_distributions.empty())
        for (const std::string& w : split_list(o.scattered_distributions))
            if (!parse_scatter_distribution(w))
                throw std::invalid_argument("--distributions: expected uniform, clustered or layered (got '" + w + "')");
    if (!o.scattered_parts.empty())
        for (const std::string& w : split_list(o.scattered_parts))
            if (w != "a" && w != "b" && w != "c") throw std::invalid_argument("--parts: expected a, b, c separated by ',' (got '" + w + "')");
    if (!o.scattered_sizes.empty()) parse_scattered_sizes(o.scattered_sizes);
}

std::vector<std::size_t> parse_scattered_sizes(const std::string& s) {
    std::vector<std::size_t> v;
    std::size_t at = 0;
    while (at < s.size()) {
        const std::size_t c = s.find(',', at);
        const std::string part = s.substr(at, c == std::string::npos ? std::string::npos : c - at);
        char* end = nullptr;
        const double x = std::strtod(part.c_str(), &end);
        if (part.empty() || end != part.c_str() + part.size() || !(x >= 10) || x > 1e8)
            throw std::invalid_argument("--sizes: expected counts 10..1e8 separated by ',' (got '" + s + "')");
        v.push_back(static_cast<std::size_t>(x));
        if (c == std::string::npos) break;
        at = c + 1;
    }
    return v;
}

void run_scattered(const BenchOptions& o, Report& r) {
    r.section("Isosurfaces straight from scattered data (dissertation chapter 5, Table 5.1)");
    const bool own_work = o.work_dir.empty();
    Ctx c(o, r);
    c.work = own_work ? fs::temp_directory_path() / fmt("meshless-bench-scattered-%d", static_cast<int>(::getpid()))
                      : fs::path(o.work_dir) / "scattered";
    c.ml = shell_quote(o.meshless);
    c.out = c.work / fmt("out-%d", static_cast<int>(::getpid()));
    std::error_code ec;
    fs::create_directories(c.out, ec);
    if (!fs::is_directory(c.out)) {
        r.note("cannot create the work folder " + c.out.string() + ": section skipped");
        return;
    }
    c.peer_limit = o.peer_timeout > 0 ? o.peer_timeout : (o.quick ? 30 : 120);
    const Proc version = run_limited(c.ml + " --version", c.out, 30);
    if (!version.ok()) {
        r.note("`" + o.meshless + " --version` failed (" + version.why(30) + "): scattered section skipped (give --meshless PATH).");
        fs::remove_all(own_work ? c.work : c.out, ec);
        return;
    }
    const std::string script = (fs::path(o.bench_dir) / "scattered_peers.py").string();
    bool peers_ok = fs::exists(script);
    if (peers_ok)
        for (const PeerDef& p : kPeers)
            peers_ok = peers_ok && run_limited(shell_quote(o.python) + " " + shell_quote(script) + " --check --method " + p.method, c.out, 60).ok();
    c.peers = peers_ok && !o.no_peers;
    r.note("Binary: " + o.meshless + " (" + first_line(version.out) + "). Work folder: " + c.work.string() +
           (own_work ? " (temporary)." : " (inputs kept and reused).") +
           (c.peers ? " Peers: " + o.python + " " + script + "."
                    : o.no_peers ? " Peers: skipped (--no-peers)." : " Peers: not run (python3 with numpy, scipy and vtk not found)."));
    const std::string parts = o.scattered_parts.empty() ? "a,b,c" : o.scattered_parts;
    if (parts.find('a') != std::string::npos) part_a(c);
    if (parts.find('b') != std::string::npos) part_b(c);
    if (parts.find('c') != std::string::npos) part_c(c);
    fs::remove_all(own_work ? c.work : c.out, ec);
}

}  // namespace meshless::bench
