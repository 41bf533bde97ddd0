// `meshless-bench multiblock`: the numbers (dissertation chapter 4, sections 4.4-4.6, Table 4.1,
// Figures 4.6-4.8), measured by running the `meshless` binary as a user would, one process per step:
//   (a) crack-free coverage on analytic fields: sphere, torus and gyroid sampled on an n^3 grid
//       (n = 41, --quick 33: 4k+1 nodes so the AMR layout keeps every cell) and written as NRRD (the
//       product has no analytic-volume writer; `meshless synth` only upsamples real volumes), then
//       `meshless split VOL --layout L` for every layout (overlapping, semi-conforming,
//       non-conforming, rotated; amr with --iso), `meshless isosurface BLOCKS --iso V --field
//       rbf-grid --stats -o pts.ply` and `meshless mc BLOCKS --iso V --stats -o naive.ply`. The points
//       are checked against the true surface (kernels/surface_coverage.hpp): coverage = fraction of a
//       dense sampling of the true isosurface (jittered grid of spacing h/4, Newton-projected, samples
//       within h/2 of the data domain's faces left out: a splat centred on a face reaches only half its
//       radius into the domain; the data domain is the volume's box, for the cell-centred AMR layout
//       the box of the finest cell centres, h/2 inside it) that lies within one splat radius of an
//       output point (target >= 99.9%);
//       mean and max distance of the points to the true surface in units of the finest cell edge h
//       (target mean <= 0.05); mean normal error in degrees against -grad f (VTK's convention;
//       normals pointing to increasing values counted apart as "reversed"). Next to them, the naive per-block marching cubes' crack edges and
//       intersecting pairs as `mc --stats` prints them ("N crack edges", "N intersecting"; with, as a
//       cross-check, the open edges of its PLY mesh after merging equal vertices, and those off the
//       domain's faces), and its coverage: the fraction of surface samples within h/4 of a mesh
//       triangle (triangles sampled on a barycentric lattice of spacing <= h/8, each lattice point a
//       disc of radius h/4). A reference row runs `meshless isosurface` on the unsplit volume
//       (chapter 3's iso-splatting) and `mc` on it (one block: no crack, open edges only on the domain
//       faces).
//   (b) speed, whole process (read + field + seeds + Newton + PLY), best of --reps: the Table 4.1 sets
//       rebuilt with `meshless split` (bucky semi-conforming --resample 33 = 21,114 nodes / 2 grids,
//       fuel overlapping --blocks 5 --resample 12 --overlap 1 = 2,880 / 5 (Table 4.1: 2,688), neghip
//       overlapping --resample 24 = 15,552 / 2 (Table 4.1: 16,000)) and the combustor (PLOT3D
//       combxyz.bin + combq.bin, 3 blocks, 47,025 nodes), at 1 and 2 threads, speed-up, identical
//       point bytes (PLY bodies; headers carry the command line), points per second of the whole
//       process, and from `--stats` the field construction time (Table 4.1's column) and the Newton
//       points per second per core; iso = the middle of the value range of the data the blocks hold (combustor: density,
//       q component 0 as `--q` reads it by default).
//   (c) when python3-vtk9 is installed: VTK's per-block contour (bench/vtk_block_contour.py:
//       vtkContourFilter on each block, cell data moved to points per block for AMR as ParaView does)
//       on the same blocks in the same run: filter time (best of reps, reading excluded), triangles,
//       open boundary edges after merging coincident points, and those off the data's bounding box
//       (the cracks); in (a) also its coverage, measured as the naive MC's.
// A command that fails (the multiblock isosurface and mc inputs are the new features) makes
// its cells "n/a (exit N: first line of stderr)"; the run goes on.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <array>
#include <utility>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "bench/bench_common.hpp"
#include "formats/json.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/nrrd_writer.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/ply_points.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/block_cells.hpp"
#include "kernels/multiblock_split.hpp"
#include "kernels/make_field.hpp"
#include "kernels/seam_gap.hpp"
#include "kernels/surface_coverage.hpp"

namespace meshless::bench {

namespace {

namespace fs = std::filesystem;

std::string first_line(const std::string& s) {
    std::string l = s.substr(0, s.find('\n'));
    if (l.size() > 100) l = l.substr(0, 100) + "...";
    for (char& c : l)
        if (static_cast<unsigned char>(c) < 0x20 || c == '|') c = ' ';
    return l;
}

// Adds `row` (its leading cells) with `why` in the next cell and "-" in the rest.
void add_na_row(Table& t, std::vector<std::string> row, const std::string& why) {
    row.push_back(why);
    row.resize(t.header.size(), "-");
    t.add(std::move(row));
}

struct Proc {
    int code = -1;
    double seconds = 0;
    std::string out, err;
    bool ok() const { return code == 0; }
    std::string why() const {
        return fmt("n/a (exit %d: %s)", code, first_line(err.empty() ? out : err).c_str());
    }
};

/// Runs `bash -c CMD` with stdout/stderr captured in files under `work`; wall clock around it.
Proc run(const std::string& cmd, const fs::path& work) {
    const fs::path o = work / "cmd.out", e = work / "cmd.err";
    const std::string full = "bash -c " + shell_quote(cmd) + " </dev/null >" + shell_quote(o.string()) + " 2>" + shell_quote(e.string());
    Proc p;
    const Stopwatch sw;
    const int st = std::system(full.c_str());
    p.seconds = sw.ms() / 1000;
    p.code = st == -1 ? -1 : WEXITSTATUS(st);
    p.out = read_file_bytes(o);
    p.err = read_file_bytes(e);
    return p;
}

/// Best of n runs (with that run's output, so --stats figures belong to the time shown); stops at
/// the first failure.
Proc best_of(const std::string& cmd, int n, const fs::path& work) {
    Proc best;
    for (int i = 0; i < n; ++i) {
        Proc p = run(cmd, work);
        if (!p.ok()) return p;
        if (i == 0 || p.seconds < best.seconds) best = std::move(p);
    }
    return best;
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

/// The number (digits, '.', ',' as a thousands separator) written just before the first occurrence
/// of `word` in `text` (case-insensitive), as in "136 crack edges" or "86920 points/s per core";
/// nullopt when the word is absent or not preceded by a number.
std::optional<double> number_before(const std::string& text, const std::string& word) {
    const std::string l = lower(text), w = lower(word);
    const std::size_t at = l.find(w);
    if (at == std::string::npos) return std::nullopt;
    std::size_t e = at;
    while (e > 0 && l[e - 1] == ' ') --e;
    std::size_t b = e;
    while (b > 0 && (std::isdigit(static_cast<unsigned char>(l[b - 1])) || l[b - 1] == '.' || l[b - 1] == ',')) --b;
    std::string digits;
    for (std::size_t i = b; i < e; ++i)
        if (l[i] != ',') digits += l[i];
    if (digits.empty() || !std::isdigit(static_cast<unsigned char>(digits[0]))) return std::nullopt;
    return std::stod(digits);
}

/// The number just after the first occurrence of `word` that is followed by one (e.g. "field 3.601 s"
/// in "... rbf-grid field from ... time: ..., field 3.601 s").
std::optional<double> number_after(const std::string& text, const std::string& word) {
    const std::string l = lower(text), w = lower(word);
    for (std::size_t at = l.find(w); at != std::string::npos; at = l.find(w, at + 1)) {
        std::size_t b = at + w.size();
        while (b < l.size() && l[b] == ' ') ++b;
        std::size_t e = b;
        while (e < l.size() && (std::isdigit(static_cast<unsigned char>(l[e])) || l[e] == '.')) ++e;
        if (e > b && std::isdigit(static_cast<unsigned char>(l[b]))) return std::stod(l.substr(b, e - b));
    }
    return std::nullopt;
}

/// "wrote X and B pieces (N nodes|cells in all)" from `meshless split`: {B, N}.
std::pair<long long, long long> split_counts(const std::string& out) {
    const std::size_t w = out.rfind("\nwrote ");
    if (w == std::string::npos) return {0, 0};
    const std::string line = out.substr(w + 1, out.find('\n', w + 1) - w - 1);
    const std::size_t a = line.rfind(" and ");
    long long b = 0, n = 0;
    if (a == std::string::npos || std::sscanf(line.c_str() + a, " and %lld pieces (%lld", &b, &n) != 2) return {0, 0};
    return {b, n};
}

std::string body_after_header(const fs::path& p) {
    const std::string s = read_file_bytes(p);
    const std::size_t h = s.find("end_header\n");
    return h == std::string::npos ? s : s.substr(h + 11);
}

struct PointCloud {
    std::vector<Vec3> pos, normal;
    std::vector<float> radius;
    std::vector<std::uint32_t> block;  ///< empty unless the PLY has a `block` property
};

PointCloud read_points(const fs::path& p) {
    PointCloud c;
    const PlyPoints pts = read_ply_points(p.string());
    for (const PointRecord& r : pts.points) {
        c.pos.push_back({r.pos[0], r.pos[1], r.pos[2]});
        c.normal.push_back({r.normal[0], r.normal[1], r.normal[2]});
        c.radius.push_back(r.radius);
    }
    c.block = pts.block;
    return c;
}

/// Coverage of a triangle mesh: its triangles sampled on a barycentric lattice of spacing <= h/8,
/// each lattice point a disc of radius tol.
std::optional<double> mesh_coverage(const fs::path& ply, const std::vector<Vec3>& samples, double h, double tol,
                                    std::string& why) {
    Mesh m;
    try {
        m = read_ply_mesh(ply.string());
    } catch (const std::exception& e) {
        why = first_line(e.what());
        return std::nullopt;
    }
    std::vector<Vec3> pts;
    const auto v = [&](std::uint32_t i) { return Vec3{m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]}; };
    for (std::size_t t = 0; t + 2 < m.tri.size(); t += 3) {
        const Vec3 a = v(m.tri[t]), b = v(m.tri[t + 1]), c = v(m.tri[t + 2]);
        const double e = std::max({norm(b - a), norm(c - b), norm(a - c)});
        const int n = std::max(1, static_cast<int>(std::ceil(e / (h / 8))));
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const double u = static_cast<double>(i) / n, w = static_cast<double>(j) / n;
                pts.push_back(a * (1 - u - w) + b * u + c * w);
            }
    }
    const std::vector<float> radii(pts.size(), static_cast<float>(tol));
    return surface_coverage(samples, pts, radii).fraction();
}

/// Open edges of a triangle mesh (edges used by exactly one triangle, vertices merged when their
/// float coordinates are equal) that do not lie on a face of the box [lo, hi] (within 1e-6 of its
/// diagonal): the cracks. -1 when the mesh cannot be read.
long long mesh_cracks(const fs::path& ply, const Vec3& lo, const Vec3& hi, long long* open = nullptr) {
    Mesh m;
    try {
        m = read_ply_mesh(ply.string());
    } catch (const std::exception&) {
        return -1;
    }
    std::map<std::array<float, 3>, std::uint32_t> ids;
    std::vector<std::uint32_t> id(m.vertex_count());
    std::vector<Vec3> pos;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const std::array<float, 3> k{m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]};
        const auto [it, fresh] = ids.emplace(k, static_cast<std::uint32_t>(pos.size()));
        if (fresh) pos.push_back({k[0], k[1], k[2]});
        id[v] = it->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (std::size_t t = 0; t + 2 < m.tri.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            std::uint32_t a = id[m.tri[t + e]], b = id[m.tri[t + (e + 1) % 3]];
            if (a == b) continue;
            if (a > b) std::swap(a, b);
            ++uses[{a, b}];
        }
    const double eps = 1e-6 * norm(hi - lo);
    long long n_open = 0, cracks = 0;
    for (const auto& [e, count] : uses) {
        if (count != 1) continue;
        ++n_open;
        const Vec3 p = pos[e.first], q = pos[e.second];
        bool on_face = false;
        for (int a = 0; a < 3 && !on_face; ++a)
            on_face = (std::abs(p[a] - lo[a]) <= eps && std::abs(q[a] - lo[a]) <= eps) ||
                      (std::abs(p[a] - hi[a]) <= eps && std::abs(q[a] - hi[a]) <= eps);
        cracks += !on_face;
    }
    if (open) *open = n_open;
    return cracks;
}

std::string pct(double f) { return fmt("%.3f", 100 * f); }

bool have_vtk(const BenchOptions& o) {
    return std::system(("'" + o.python + "' -c 'import vtk' >/dev/null 2>&1").c_str()) == 0;
}

struct VtkContour {
    bool ok = false;
    std::string why;
    double seconds = 0;
    long long triangles = 0, boundary = 0, cracks = 0;
};

/// bench/vtk_block_contour.py on `inputs` (a .vtm, a .vthb, or "--plot3d XYZ Q").
VtkContour vtk_contour(const BenchOptions& o, const std::string& inputs, double iso, int reps, const fs::path& work,
                       const fs::path& ply_out = {}) {
    VtkContour v;
    const std::string script = (fs::path(o.bench_dir) / "vtk_block_contour.py").string();
    if (!fs::exists(script)) {
        v.why = "n/a (vtk_block_contour.py not found)";
        return v;
    }
    const Proc p = run(shell_quote(o.python) + " " + shell_quote(script) + " " + inputs + fmt(" --iso %.17g --reps %d", iso, reps) +
                           (ply_out.empty() ? std::string() : " --ply-out " + shell_quote(ply_out.string())),
                       work);
    if (!p.ok()) {
        v.why = p.why();
        return v;
    }
    try {
        const Json j = parse_json(p.out, "vtk_block_contour.py output");
        const auto num = [&](const char* k) {
            const Json* x = j.find(k);
            if (!x || !x->is_number()) throw std::runtime_error(std::string("no number '") + k + "'");
            return x->num;
        };
        v.seconds = num("best_seconds");
        v.triangles = static_cast<long long>(num("triangles"));
        v.boundary = static_cast<long long>(num("boundary_edges"));
        v.cracks = static_cast<long long>(num("crack_edges"));
        v.ok = true;
    } catch (const std::exception& e) {
        v.why = "n/a (unreadable output: " + first_line(e.what()) + ")";
    }
    return v;
}

// ---- (a) analytic coverage ------------------------------------------------------------------------

void part_a(const BenchOptions& o, Report& r, const fs::path& work, bool vtk) {
    const std::int64_t n = o.quick ? 33 : 41;
    const double h = 2.0 / static_cast<double>(n - 1);
    r.section(fmt("(a) Crack-free coverage on analytic fields, %lld^3 grid (finest cell edge h = %.4g)",
                  static_cast<long long>(n), h));
    r.note("Points: `meshless isosurface BLOCKS --iso V --field rbf-grid --stats -o pts.ply` on the blocks of `meshless split`. "
           "Coverage: fraction of a dense sampling of the true isosurface (jittered grid, spacing h/4, Newton-projected; "
           "samples within h/2 of the data domain's faces left out; amr: the data domain is the box of the finest cell "
           "centres, h/2 inside the volume's) within one splat radius of an output point, target >= 99.9%. "
           "Distances to the true surface in units of h (target mean <= 0.05). Normal error: degrees from -grad f (VTK's convention; normals towards increasing values counted as reversed). "
           "Naive MC: `meshless mc BLOCKS --iso V --stats` (crack edges, intersecting pairs as it prints them; coverage = "
           "samples within h/4 of a triangle).");
    const fs::path dir = work / "analytic";
    fs::create_directories(dir);
    Table t;
    t.header = {"field", "layout", "blocks", "nodes", "points", "coverage %", "mean dist / h", "max dist / h",
                "normal err deg", "isosurface s", "MC crack edges", "MC intersecting pairs", "MC coverage %"};
    if (vtk) {
        t.header.push_back("VTK crack edges");
        t.header.push_back("VTK coverage %");
    }
    const std::vector<std::pair<std::string, std::string>> layouts = {
        {"volume", ""}, {"overlapping", "--layout overlapping"}, {"semi-conforming", "--layout semi-conforming"},
        {"non-conforming", "--layout non-conforming"}, {"rotated", "--layout rotated"}, {"amr", "--layout amr"}};
    for (AnalyticField f : {AnalyticField::sphere, AnalyticField::torus, AnalyticField::gyroid}) {
        const double iso = default_iso(f);
        const std::string fname = to_string(f);
        const fs::path vol = dir / (fname + ".nrrd");
        write_nrrd(make_analytic_volume(f, n), vol.string(), "meshless-bench multiblock: analytic " + fname);
        // the data domain: the volume's box for node-centred layouts; for the cell-centred AMR layout
        // the box of the finest cell centres, h/2 inside it. Samples within h/2 of the data domain's
        // faces are left out (a splat centred on a face reaches only half its radius into the domain).
        SurfaceSampling ss;
        ss.spacing = h / 4;
        ss.margin = h / 2;
        const std::vector<Vec3> node_samples = sample_isosurface(f, iso, Box3{{-1, -1, -1}, {1, 1, 1}}, ss);
        ss.margin = h;
        const std::vector<Vec3> cell_samples = sample_isosurface(f, iso, Box3{{-1, -1, -1}, {1, 1, 1}}, ss);
        std::fprintf(stderr, "multiblock: %s, %zu / %zu surface samples\n", fname.c_str(), node_samples.size(),
                     cell_samples.size());
        for (const auto& [lname, lopt] : layouts) {
            const std::vector<Vec3>& samples = lname == "amr" ? cell_samples : node_samples;
            std::vector<std::string> row{fname, lname};
            std::string input = vol.string();
            std::string blocks = "1", nodes = fmt("%lld", static_cast<long long>(n * n * n));
            if (!lopt.empty()) {
                const bool amr = lname == "amr";
                const fs::path idx = dir / (fname + "-" + lname + (amr ? ".vthb" : ".vtm"));
                const Proc sp = run(shell_quote(o.meshless) + " split " + shell_quote(vol.string()) + " " + lopt +
                                        (amr ? fmt(" --iso %.17g", iso) : std::string()) + " -o " + shell_quote(idx.string()),
                                    dir);
                if (!sp.ok()) {
                    add_na_row(t, std::move(row), sp.why());
                    continue;
                }
                input = idx.string();
                const auto [b, nn] = split_counts(sp.out);
                blocks = fmt("%lld", b);
                nodes = fmt("%lld", nn);
            }
            row.push_back(blocks);
            row.push_back(nodes);
            const fs::path pts = dir / (fname + "-" + lname + ".ply");
            fs::remove(pts);
            const Proc iso_run = run(shell_quote(o.meshless) + " isosurface " + shell_quote(input) + fmt(" --iso %.17g", iso) +
                                         (lopt.empty() ? std::string() : std::string(" --field rbf-grid --stats")) +
                                         " -o " + shell_quote(pts.string()),
                                     dir);
            if (!iso_run.ok()) {
                row.push_back(iso_run.why());
                for (int i = 0; i < 5; ++i) row.push_back("-");
            } else {
                try {
                    const PointCloud c = read_points(pts);
                    const CoverageResult cov = surface_coverage(samples, c.pos, c.radius);
                    const PointErrors pe = point_errors(f, iso, c.pos, c.normal);
                    row.push_back(fmt("%zu", c.pos.size()));
                    row.push_back(pct(cov.fraction()) + (cov.fraction() >= 0.999 ? "" : " (below 99.9)"));
                    row.push_back(fmt("%.4f", pe.mean_distance / h));
                    row.push_back(fmt("%.3f", pe.max_distance / h));
                    row.push_back(fmt("%.2f", pe.mean_normal_deg) +
                                  (pe.reversed ? fmt(" (%zu reversed)", pe.reversed) : std::string()));
                    row.push_back(fmt("%.3f", iso_run.seconds));
                } catch (const std::exception& e) {
                    row.push_back("n/a (" + first_line(e.what()) + ")");
                    for (int i = 0; i < 5; ++i) row.push_back("-");
                }
            }
            const fs::path naive = dir / (fname + "-" + lname + "-mc.ply");
            fs::remove(naive);
            const Proc mc = run(shell_quote(o.meshless) + " mc " + shell_quote(input) + fmt(" --iso %.17g", iso) + " --stats -o " +
                                    shell_quote(naive.string()),
                                dir);
            if (!mc.ok()) {
                row.push_back(mc.why());
                row.push_back("-");
                row.push_back("-");
            } else {
                const std::string stats = mc.err + "\n" + mc.out;
                const auto cracks = number_before(stats, "crack edges");
                const auto inter = number_before(stats, "intersecting");
                long long open = 0;
                const long long mine = mesh_cracks(naive, {-1, -1, -1}, {1, 1, 1}, &open);
                const std::string check = mine < 0 ? std::string(" (mesh unreadable)")
                                                   : fmt(" (mesh: %lld open, %lld off the box)", open, mine);
                row.push_back((cracks ? fmt("%.0f", *cracks) : "? (not in --stats)") + check);
                row.push_back(inter ? fmt("%.0f", *inter) : "? (not in --stats)");
                std::string why;
                const auto mcov = mesh_coverage(naive, samples, h, h / 4, why);
                row.push_back(mcov ? pct(*mcov) : "n/a (" + why + ")");
            }
            if (vtk && lopt.empty()) {
                row.push_back("-");
                row.push_back("-");
            } else if (vtk) {
                const fs::path vply = dir / (fname + "-" + lname + "-vtk.ply");
                const VtkContour vc = vtk_contour(o, "--input " + shell_quote(input), iso, 1, dir, vply);
                row.push_back(vc.ok ? fmt("%lld (of %lld open)", vc.cracks, vc.boundary) : vc.why);
                std::string why;
                const auto vcov = vc.ok ? mesh_coverage(vply, samples, h, h / 4, why) : std::nullopt;
                row.push_back(vcov ? pct(*vcov) : "-");
            }
            t.add(row);
        }
    }
    r.table(t);
}

// ---- (b) speed on the Table 4.1 sets and the combustor -------------------------------------------

struct SpeedSet {
    std::string label, paper;      ///< label; Table 4.1's points / grids / field time
    std::vector<std::string> inputs;  ///< files for `isosurface` (after split)
    std::string vtk_input;         ///< arguments for vtk_block_contour.py
    double iso = 0;
    std::string why;               ///< non-empty: not available
    long long nodes = 0, blocks = 0;
};

double middle_of_range(const std::vector<std::string>& paths, const PointSetOptions& opt) {
    const Multiblock mb = read_multiblock(paths, opt);
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& b : mb.blocks)
        for (std::size_t i = 0; i < b.value.size(); ++i)
            if (b.is_valid(static_cast<std::int64_t>(i)) && std::isfinite(b.value[i])) lo = std::min(lo, b.value[i]), hi = std::max(hi, b.value[i]);
    return 0.5 * (lo + hi);
}

SpeedSet split_set(const BenchOptions& o, const fs::path& dir, const std::string& label, const std::string& paper,
                   const std::string& rel, const std::string& split_args, std::int64_t resample) {
    SpeedSet s;
    s.label = label;
    s.paper = paper;
    const fs::path vol = fs::path(o.data_dir) / rel;
    if (!fs::exists(vol)) {
        s.why = "n/a (" + rel + " not in the data folder)";
        return s;
    }
    const fs::path idx = dir / (label + ".vtm");
    const Proc sp = run(shell_quote(o.meshless) + " split " + shell_quote(vol.string()) + " " + split_args + " -o " + shell_quote(idx.string()), dir);
    if (!sp.ok()) {
        s.why = sp.why();
        return s;
    }
    std::tie(s.blocks, s.nodes) = split_counts(sp.out);
    s.inputs = {idx.string()};
    s.vtk_input = "--input " + shell_quote(idx.string());
    // iso: the middle of the value range of the resampled volume the blocks hold (`split --resample`)
    const Volume v = resample_volume(read_volume(vol.string()).view(), resample);
    const auto rg = v.value_range();
    s.iso = std::floor(0.5 * (rg[0] + rg[1])) + 0.5;
    return s;
}

void part_b(const BenchOptions& o, Report& r, const fs::path& work, bool vtk) {
    r.section("(b) Speed: the Table 4.1 sets and the combustor, whole process at 1 and 2 threads");
    r.note(fmt("`meshless isosurface BLOCKS --iso V --field rbf-grid --stats --threads T -o out.ply`, wall clock of the whole process "
               "(read + field + seeds + Newton + PLY), best of %d. Target: bucky, fuel, neghip <= 1 s, combustor <= 2 s on one "
               "core; 2 threads >= 1.8x with identical point bytes (PLY bodies). Table 4.1 (2.8 GHz Pentium 4) timed the "
               "field construction alone. VTK: vtkContourFilter per block (filter time only), open edges after merging "
               "coincident points, cracks = those off the bounding box.", o.process_reps));
    const fs::path dir = work / "speed";
    fs::create_directories(dir);
    std::vector<SpeedSet> sets;
    sets.push_back(split_set(o, dir, "bucky", "21,114 / 2 / 1 min 42 s", "bucky/Bucky_32x32x32_uint8.raw",
                             "--layout semi-conforming --resample 33", 33));
    sets.push_back(split_set(o, dir, "fuel", "2,688 / 5 / 5 s", "fuel/fuel_64x64x64_uint8.raw",
                             "--layout overlapping --blocks 5 --resample 12 --overlap 1", 12));
    sets.push_back(split_set(o, dir, "neghip", "16,000 / 2 / 50 s", "neghip/neghip_64x64x64_uint8.raw",
                             "--layout overlapping --resample 24", 24));
    {
        SpeedSet c;
        c.label = "combustor";
        c.paper = "-";
        const fs::path xyz = fs::path(o.data_dir) / "plot3d/combxyz.bin", q = fs::path(o.data_dir) / "plot3d/combq.bin";
        if (!fs::exists(xyz) || !fs::exists(q)) {
            c.why = "n/a (plot3d/combxyz.bin, combq.bin not in the data folder)";
        } else {
            c.inputs = {xyz.string(), "--q", q.string()};
            c.vtk_input = "--plot3d " + shell_quote(xyz.string()) + " " + shell_quote(q.string());
            try {
                PointSetOptions opt;
                opt.q_file = q.string();
                const Multiblock mb = read_multiblock({xyz.string()}, opt);
                c.blocks = static_cast<long long>(mb.blocks.size());
                for (const auto& b : mb.blocks) c.nodes += b.node_count();
                c.iso = middle_of_range({xyz.string()}, opt);
            } catch (const std::exception& e) {
                c.why = "n/a (" + first_line(e.what()) + ")";
            }
        }
        sets.push_back(c);
    }
    Table t;
    t.header = {"set", "Table 4.1 points / grids / field", "blocks", "nodes", "iso", "points", "1 thread s", "2 threads s",
                "speed-up", "same bytes", "points/s (1 thread)", "field s (1 thread)", "Newton points/s per core"};
    if (vtk) {
        t.header.push_back("VTK contour s");
        t.header.push_back("VTK triangles");
        t.header.push_back("VTK open / crack edges");
    }
    for (const SpeedSet& s : sets) {
        std::vector<std::string> row{s.label, s.paper};
        if (!s.why.empty()) {
            add_na_row(t, std::move(row), s.why);
            continue;
        }
        row.push_back(fmt("%lld", s.blocks));
        row.push_back(fmt("%lld", s.nodes));
        row.push_back(fmt("%.6g", s.iso));
        std::string in;
        for (const auto& p : s.inputs) {
            in += ' ';
            in += shell_quote(p);
        }
        Proc t1, t2;
        const fs::path o1 = dir / (s.label + "-t1.ply"), o2 = dir / (s.label + "-t2.ply");
        for (int th : {1, 2}) {
            (th == 1 ? t1 : t2) = best_of(shell_quote(o.meshless) + " isosurface" + in + fmt(" --iso %.17g --field rbf-grid --stats --threads %d -o ", s.iso, th) +
                                              shell_quote((th == 1 ? o1 : o2).string()),
                                          o.process_reps, dir);
        }
        if (!t1.ok()) {
            row.push_back(t1.why());
            row.resize(vtk ? t.header.size() - 3 : t.header.size(), "-");  // the VTK cells follow
        } else {
            std::size_t npts = 0;
            try {
                npts = read_points(o1).pos.size();
            } catch (const std::exception&) {
            }
            row.push_back(fmt("%zu", npts));
            row.push_back(fmt("%.3f", t1.seconds));
            row.push_back(t2.ok() ? fmt("%.3f", t2.seconds) : t2.why());
            row.push_back(t2.ok() ? fmt("%.2fx", t1.seconds / t2.seconds) : "-");
            row.push_back(t2.ok() ? (body_after_header(o1) == body_after_header(o2) ? "SAME" : "DIFFERENT") : "-");
            row.push_back(fmt("%.0f", static_cast<double>(npts) / t1.seconds));
            const auto field_s = number_after(t1.err, "field ");
            const auto newton = number_before(t1.err, "points/s per core");
            row.push_back(field_s ? fmt("%.3f", *field_s) : "? (not in --stats)");
            row.push_back(newton ? fmt("%.0f", *newton) : "? (not in --stats)");
        }
        if (vtk) {
            const VtkContour vc = vtk_contour(o, s.vtk_input, s.iso, std::max(3, o.process_reps), dir);
            if (vc.ok) {
                row.push_back(fmt("%.4f", vc.seconds));
                row.push_back(fmt("%lld", vc.triangles));
                row.push_back(fmt("%lld / %lld", vc.boundary, vc.cracks));
            } else {
                row.push_back(vc.why);
                row.push_back("-");
                row.push_back("-");
            }
        }
        t.add(row);
    }
    r.table(t);
}

// ---- (c) the seam test on real data ------------------------------------------------------------

/// Smallest and median diagonal of the blocks' usable cells (the Newton tolerance is 0.01 x a seed's).
std::array<double, 2> cell_diagonals(const Multiblock& mb) {
    std::vector<double> d;
    HexCell cell;
    std::array<std::int64_t, 8> node{};
    for (const auto& b : mb.blocks)
        for (std::int64_t k = 0; k + 1 < b.dims[2]; ++k)
            for (std::int64_t j = 0; j + 1 < b.dims[1]; ++j)
                for (std::int64_t i = 0; i + 1 < b.dims[0]; ++i) {
                    if (!gather_block_cell(b, i, j, k, cell, node)) continue;
                    double l = 0;
                    for (int q = 0; q < 4; ++q) l = std::max(l, norm(cell.corner[static_cast<std::size_t>(7 - q)] - cell.corner[static_cast<std::size_t>(q)]));
                    d.push_back(l);
                }
    if (d.empty()) return {0, 0};
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    const double median = d[d.size() / 2];
    return {*std::min_element(d.begin(), d.end()), median};
}

void part_c(const BenchOptions& o, Report& r, const fs::path& work) {
    r.section("(c) Seam test on the real AMR sets and the 3-block combustor");
    r.note("`meshless isosurface BLOCKS --iso V --field rbf-grid -o pts.ply`; pairs of points seeded in different blocks "
           "whose splats overlap (|p_i - p_j| <= max radius); gap = distance of p_i from j's tangent plane "
           "(kernels/seam_gap.hpp). Target: points of different blocks on one surface, gap <= the Newton tolerance "
           "(0.01 x the seed's cell diagonal) plus the curvature term r^2 kappa / 2 of two points a splat radius apart "
           "on a curved surface. Tolerance column: 0.01 x the smallest / median cell diagonal.");
    const fs::path dir = work / "seam";
    std::error_code ec;
    fs::create_directories(dir, ec);
    struct Set {
        std::string label;
        std::vector<std::string> paths;
        std::string options;
        double iso;
    };
    const fs::path D(o.data_dir);
    const std::vector<Set> sets = {
        {"chombo3d (AMR, 16 boxes)", {(D / "amr/chombo3d/chombo3d.vtm").string()}, "", -0.02},
        {"HierarchicalBoxDataset.v1.1 (AMR, 81 boxes)", {(D / "amr/HierarchicalBoxDataset.v1.1.vthb").string()},
         " --value 'Fractal Volume Fraction'", 1.0},
        {"combustor multicomb_0..2.vts", {(D / "plot3d/multicomb_0.vts").string(), (D / "plot3d/multicomb_1.vts").string(),
                                          (D / "plot3d/multicomb_2.vts").string()}, "", 0.4},
    };
    Table t;
    t.header = {"set", "iso", "blocks", "points", "pairs across blocks", "max gap", "p99 gap", "p99 gap within blocks",
                "tolerance (min / median cell)", "max |f-iso|/|grad f| of the points", "/ min tolerance"};
    for (const Set& s : sets) {
        std::vector<std::string> row{s.label, fmt("%g", s.iso)};
        bool present = true;
        std::string in;
        for (const auto& p : s.paths) {
            present = present && fs::exists(p);
            in += " " + shell_quote(p);
        }
        if (!present) {
            add_na_row(t, std::move(row), "n/a (data not found)");
            continue;
        }
        const fs::path out = dir / "seam.ply";
        const Proc p = run(shell_quote(o.meshless) + " isosurface" + in + s.options + fmt(" --iso %.17g --field rbf-grid -o ", s.iso) +
                               shell_quote(out.string()),
                           dir);
        if (!p.ok()) {
            add_na_row(t, std::move(row), p.why());
            continue;
        }
        PointSetOptions opt;
        if (!s.options.empty()) opt.value_name = "Fractal Volume Fraction";
        const Multiblock mb = read_multiblock(s.paths, opt);
        const auto diag = cell_diagonals(mb);
        const PointCloud c = read_points(out);
        const SeamGaps g = seam_gaps(c.pos, c.normal, c.radius, c.block, std::numeric_limits<double>::infinity());
        row.push_back(fmt("%zu", mb.blocks.size()));
        row.push_back(fmt("%zu", c.pos.size()));
        row.push_back(fmt("%llu", static_cast<unsigned long long>(g.pairs)));
        row.push_back(fmt("%.3g", g.max_gap));
        row.push_back(fmt("%.3g", g.p99_gap));
        const SeamGaps w = seam_gaps(c.pos, c.normal, c.radius, c.block, std::numeric_limits<double>::infinity(), false);
        row.push_back(fmt("%.3g", w.p99_gap));
        row.push_back(fmt("%.3g / %.3g", 0.01 * diag[0], 0.01 * diag[1]));
        // every point's first-order distance to the one surface of the field (the same default rbf-grid
        // the command built): two points within tolerance of one surface are within 2 x tolerance of each
        // other's surfaces
        const auto field = make_field(to_point_set(mb), FieldParams{});
        std::vector<double> v(c.pos.size());
        std::vector<Vec3> gr(c.pos.size());
        field->evaluate(c.pos, v, gr);
        double worst = 0;
        for (std::size_t i = 0; i < v.size(); ++i)
            if (norm(gr[i]) > 0) worst = std::max(worst, std::abs(v[i] - s.iso) / norm(gr[i]));
        row.push_back(fmt("%.3g", worst));
        row.push_back(diag[0] > 0 ? fmt("%.2f", worst / (0.01 * diag[0])) : "-");
        t.add(row);
    }
    r.table(t);
}

}  // namespace

void run_multiblock(const BenchOptions& o, Report& r) {
    r.section("Multiblock and AMR isosurfaces (dissertation chapter 4, Table 4.1, Figures 4.6-4.8)");
    std::error_code ec;
    fs::path work;
    bool temp = false;
    if (!o.work_dir.empty()) {
        work = fs::path(o.work_dir) / "multiblock";
    } else {
        work = fs::temp_directory_path() / fmt("meshless-bench-multiblock-%d", static_cast<int>(::getpid()));
        temp = true;
    }
    fs::create_directories(work, ec);
    if (!fs::is_directory(work)) {
        r.note("cannot create the work folder " + work.string() + ": section skipped");
        return;
    }
    const bool vtk = have_vtk(o);
    r.note(std::string("Binary: ") + o.meshless + ". " +
           (vtk ? "VTK columns from bench/vtk_block_contour.py (" + o.python + ")."
                : "python3-vtk9 not installed: the VTK columns are left out."));
    part_a(o, r, work, vtk);
    part_b(o, r, work, vtk);
    part_c(o, r, work);
    if (temp && !o.keep) fs::remove_all(work, ec);
}

}  // namespace meshless::bench
