// meshless-bench speed / threads: extraction time and memory of paradigm-(C) iso-splatting vs our
// marching cubes vs VTK's Flying Edges (dissertation §3.6, Fig. 3.5: 16 isosurfaces x 10 runs per
// data set, mean time per isosurface), and thread scaling with identical output bytes.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>

#include "bench/bench_common.hpp"
#include "formats/atomic_file.hpp"
#include "formats/json.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/cell_sampling.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/project_sample.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"

namespace meshless::bench {

namespace {

constexpr double kTargetRatio = 0.5;  // "iso-splatting extracts in about half the time" (§3.6)

struct LoadedVolume {
    std::string label;
    std::string source;  ///< path or "analytic"
    Volume vol;
};

/// The speed volumes present under the data folder (quick mode skips the large ones); when the
/// folder is missing, two analytic float volumes so the tables are still produced.
std::vector<LoadedVolume> load_volumes(const BenchOptions& o, Report& r) {
    std::vector<LoadedVolume> out;
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!o.data_dir.empty() && fs::is_directory(o.data_dir, ec)) {
        std::string missing, skipped;
        for (const DataVolume& d : speed_volumes()) {
            const std::string path = (fs::path(o.data_dir) / d.rel_path).string();
            if (!fs::exists(path, ec)) {
                missing += (missing.empty() ? "" : ", ") + d.rel_path;
                continue;
            }
            if (o.quick && d.large) {
                skipped += (skipped.empty() ? "" : ", ") + d.label;
                continue;
            }
            try {
                out.push_back({d.label, path, read_volume(path)});
            } catch (const std::exception& e) {
                r.note(fmt("could not read %s: %s", path.c_str(), e.what()));
            }
        }
        if (!missing.empty()) r.note("not found under " + o.data_dir + ": " + missing);
        if (!skipped.empty()) r.note("--quick: skipped large volume(s): " + skipped);
    } else {
        r.note("data folder '" + o.data_dir + "' not found (give --data DIR or set MESHLESS_DATA); "
               "using analytic float32 volumes instead");
    }
    if (out.empty()) {
        const std::int64_t n = o.quick ? 64 : 128;
        out.push_back({fmt("analytic sphere %lld^3", static_cast<long long>(n)), "analytic",
                       make_analytic_volume(AnalyticField::sphere, n)});
        out.push_back({fmt("analytic gyroid %lld^3", static_cast<long long>(n)), "analytic",
                       make_analytic_volume(AnalyticField::gyroid, n)});
    }
    return out;
}

std::string dims_str(const GridSpec& g) {
    return fmt("%lldx%lldx%lld", static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]),
               static_cast<long long>(g.dims[2]));
}

std::string ratio_cell(double num, double den, bool with_target) {
    if (!(den > 0)) return "-";
    const double q = num / den;
    return with_target ? fmt("%.2f %s", q, q <= kTargetRatio ? "PASS" : "FAIL") : fmt("%.2f", q);
}

// ---- VTK baseline ---------------------------------------------------------------------------

bool vtk_available(const BenchOptions& o) {
    const std::string cmd = "'" + o.python + "' -c 'import vtk' >/dev/null 2>&1";
    const int st = std::system(cmd.c_str());
    return st != -1 && WIFEXITED(st) && WEXITSTATUS(st) == 0;
}

/// A directory under the system temp folder, removed (with its contents) by the destructor.
struct ScratchDir {
    std::filesystem::path path;
    ScratchDir() {
        path = std::filesystem::temp_directory_path() / ("meshless-bench-" + std::to_string(::getpid()));
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
};

struct FeResult {
    double mean_ms = 0;
    double mean_triangles = 0;
    std::string backend, version;
};

/// Runs bench/flying_edges.py on a raw dump of the volume; nullopt (with a note) on failure.
std::optional<FeResult> run_flying_edges(const BenchOptions& o, const Volume& v, const std::vector<double>& isos,
                                         int reps, const ScratchDir& scratch, Report& r) {
    const std::string script = (std::filesystem::path(o.bench_dir) / "flying_edges.py").string();
    if (!std::filesystem::exists(script)) {
        r.note("flying_edges.py not found in '" + o.bench_dir + "' (give --bench-dir): FE column skipped");
        return std::nullopt;
    }
    const std::string raw = (scratch.path / "volume.raw").string();
    {
        AtomicFile f(raw);
        f.write(v.bytes.data(), v.bytes.size());
        f.commit();
    }
    std::string iso_list;
    for (double x : isos) {
        if (!iso_list.empty()) iso_list += ',';
        iso_list += fmt("%.17g", x);
    }
    const GridSpec& g = v.grid;
    // "--opt=value": negative lists such as -1,-1,-1 would otherwise read as options to argparse
    const std::string cmd = fmt("'%s' '%s' --raw '%s' --dims=%lld,%lld,%lld --type=%s --spacing=%.17g,%.17g,%.17g "
                                "--origin=%.17g,%.17g,%.17g --isos=%s --reps=%d",
                                o.python.c_str(), script.c_str(), raw.c_str(), static_cast<long long>(g.dims[0]),
                                static_cast<long long>(g.dims[1]), static_cast<long long>(g.dims[2]),
                                to_string(v.type), g.spacing[0], g.spacing[1], g.spacing[2], g.origin[0],
                                g.origin[1], g.origin[2], iso_list.c_str(), reps);
    std::FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) {
        r.note("could not start " + o.python + ": FE column skipped");
        return std::nullopt;
    }
    std::string text;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) text.append(buf, n);
    const int st = ::pclose(p);
    if (st == -1 || !WIFEXITED(st) || WEXITSTATUS(st) != 0) {
        r.note(fmt("flying_edges.py failed (exit status %d): FE column skipped", st == -1 ? -1 : WEXITSTATUS(st)));
        return std::nullopt;
    }
    try {
        const Json j = parse_json(text, script + " output");
        FeResult fe;
        const Json* ms = j.find("mean_seconds");
        const Json* per = j.find("per_iso");
        if (!ms || !ms->is_number() || !per || !per->is_array() || per->arr.empty())
            throw std::runtime_error("missing mean_seconds or per_iso");
        fe.mean_ms = ms->num * 1e3;
        for (const Json& e : per->arr)
            if (const Json* t = e.find("triangles"); t && t->is_number()) fe.mean_triangles += t->num;
        fe.mean_triangles /= static_cast<double>(per->arr.size());
        if (const Json* b = j.find("smp_backend"); b && b->is_string()) fe.backend = b->str;
        if (const Json* b = j.find("vtk_version"); b && b->is_string()) fe.version = b->str;
        return fe;
    } catch (const std::exception& e) {
        r.note(std::string("flying_edges.py: unreadable output: ") + e.what());
        return std::nullopt;
    }
}

// ---- timing ---------------------------------------------------------------------------------

struct Timed {
    double is_ms = 0, mc_ms = 0;       // mean per isosurface
    double points = 0, triangles = 0;  // mean per isosurface
    double mc_vertices = 0;
    double is_bytes = 0, mc_bytes = 0;
};

Timed time_is_vs_mc(const Volume& vol, const std::vector<double>& isos, int reps) {
    Timed t;
    const VolumeView view = vol.view();
    {  // warm-up: page in the volume, grow the allocator's arenas
        CollectSink s;
        run_isosplat(view, isos[isos.size() / 2], Projection::approx, SamplingParams{}, s, RunOptions{1});
        (void)marching_cubes(view, isos[isos.size() / 2]);
    }
    for (double iso : isos) {
        for (int rep = 0; rep < reps; ++rep) {
            // interleaved so that both methods see the same machine conditions
            // both outputs stay in memory past the stopwatch (freeing is timed for neither); the
            // points stay in the batches' own arrays (no copy into one array, as the mesh does not
            // get copied either)
            std::size_t npts;
            CollectSink s(/*keep_chunks=*/true);
            {
                Stopwatch sw;
                run_isosplat(view, iso, Projection::approx, SamplingParams{}, s, RunOptions{1});
                npts = s.size();
                t.is_ms += sw.ms();
            }
            Mesh m;
            {
                Stopwatch sw;
                m = marching_cubes(view, iso);
                t.mc_ms += sw.ms();
            }
            if (rep == 0) {
                t.points += static_cast<double>(npts);
                t.is_bytes += static_cast<double>(npts * sizeof(PointRecord));
                t.triangles += static_cast<double>(m.triangle_count());
                t.mc_vertices += static_cast<double>(m.vertex_count());
                t.mc_bytes += static_cast<double>(m.memory_bytes());
            }
        }
    }
    const double n = static_cast<double>(isos.size());
    t.is_ms /= n * reps;
    t.mc_ms /= n * reps;
    t.points /= n;
    t.triangles /= n;
    t.mc_vertices /= n;
    t.is_bytes /= n;
    t.mc_bytes /= n;
    return t;
}

/// Where iso-splatting's time goes at one isovalue: the sampling kernel alone, the projection
/// kernel alone (both single-threaded loops without the stage graph), the two-stage pipeline (as
/// the piped commands run) and the default (fused generate+project) pipeline that IS ms measures.
struct Breakdown {
    double generate_ms = 0, project_ms = 0, two_stage_ms = 0, pipeline_ms = 0;
    std::int64_t samples = 0;
};

Breakdown breakdown(const Volume& vol, double iso, int reps) {
    Breakdown b;
    const VolumeView view = vol.view();
    const std::int64_t rows = cell_row_count(vol.grid);
    // buffers kept across repetitions (capacity reused), so the kernels are timed, not page faults
    std::vector<SampleRecord> samples;
    std::vector<PointRecord> pts;
    for (int rep = -1; rep < reps; ++rep) {  // rep -1: warm-up, not timed
        samples.clear();
        pts.clear();
        SamplingStats ss;
        Stopwatch sw;
        sample_active_cells(view, iso, 0, rows, SamplingParams{}, samples, ss);
        const double g_ms = sw.ms();
        pts.reserve(samples.size());
        ProjectionStats ps;
        Stopwatch sw2;
        PointRecord p;
        for (const SampleRecord& s : samples)
            if (project_sample(s, iso, Projection::approx, p, ps)) pts.push_back(p);
        const double p_ms = sw2.ms();
        b.samples = static_cast<std::int64_t>(samples.size());
        CollectSink sink2;
        Stopwatch sw3;
        run_isosplat(view, iso, Projection::approx, SamplingParams{}, sink2, RunOptions{1}, PipelineShape::two_stage);
        const double s_ms = sw3.ms();
        CollectSink sink;
        Stopwatch sw4;
        run_isosplat(view, iso, Projection::approx, SamplingParams{}, sink, RunOptions{1});
        const double t_ms = sw4.ms();
        if (rep < 0) continue;
        b.generate_ms += g_ms;
        b.project_ms += p_ms;
        b.two_stage_ms += s_ms;
        b.pipeline_ms += t_ms;
    }
    b.generate_ms /= reps;
    b.project_ms /= reps;
    b.two_stage_ms /= reps;
    b.pipeline_ms /= reps;
    return b;
}

}  // namespace

void run_speed(const BenchOptions& o, Report& r) {
    r.section("Speed: iso-splatting vs marching cubes vs VTK Flying Edges (dissertation 3.6)");
    const int reps = o.reps, k = o.isovalues;
    r.note(fmt("Single thread. Per volume: %d isovalues between grey levels (evenly spaced quantiles of the "
               "histogram, x.5 for integer data), %d repetitions each; mean wall time per isosurface. "
               "IS = paradigm (C) iso-splatting with the approximate projection (Eq. 3.5), points kept in memory "
               "(CollectSink); MC = our marching cubes, indexed mesh with per-vertex normals in memory; "
               "FE = vtkFlyingEdges3D (normals on, sequential SMP backend). Target: IS/MC and IS/FE <= %.1f.",
               k, reps, kTargetRatio));
    std::vector<LoadedVolume> vols = load_volumes(o, r);
    const bool vtk = vtk_available(o);
    if (!vtk) r.note("VTK not installed (apt-get install python3-vtk9): FE column skipped");
    std::optional<ScratchDir> scratch;
    if (vtk) scratch.emplace();

    Table times, sizes, where;
    times.header = {"volume", "dims", "type", "isos", "IS ms", "MC ms", "IS/MC", "FE ms", "IS/FE", "IS Mpts/s"};
    sizes.header = {"volume", "points", "MC vertices", "MC triangles", "FE triangles", "IS memory", "MC memory", "IS/MC memory"};
    where.header = {"volume", "iso", "samples", "generate ms", "project ms", "kernels sum", "2-stage pipeline ms",
                    "fused pipeline ms"};
    std::string fe_info;
    for (const LoadedVolume& lv : vols) {
        const std::vector<double> isos = pick_isovalues(lv.vol, k);
        if (isos.empty()) {
            r.note(lv.label + ": constant volume, skipped");
            continue;
        }
        std::fprintf(stderr, "bench speed: %s (%zu isovalues x %d reps)...\n", lv.label.c_str(), isos.size(), reps);
        const Timed t = time_is_vs_mc(lv.vol, isos, reps);
        std::optional<FeResult> fe;
        if (vtk) fe = run_flying_edges(o, lv.vol, isos, reps, *scratch, r);
        if (fe && fe_info.empty()) fe_info = "VTK " + fe->version + ", SMP backend " + fe->backend;
        times.add({lv.label, dims_str(lv.vol.grid), to_string(lv.vol.type), fmt("%zu", isos.size()),
                   fmt("%.3f", t.is_ms), fmt("%.3f", t.mc_ms), ratio_cell(t.is_ms, t.mc_ms, true),
                   fe ? fmt("%.3f", fe->mean_ms) : "-", fe ? ratio_cell(t.is_ms, fe->mean_ms, true) : "-",
                   t.is_ms > 0 ? fmt("%.1f", t.points / (t.is_ms * 1e3)) : "-"});
        sizes.add({lv.label, fmt("%.0f", t.points), fmt("%.0f", t.mc_vertices), fmt("%.0f", t.triangles),
                   fe ? fmt("%.0f", fe->mean_triangles) : "-", bytes_str(t.is_bytes), bytes_str(t.mc_bytes),
                   ratio_cell(t.is_bytes, t.mc_bytes, false)});
        const double mid = isos[isos.size() / 2];
        const Breakdown b = breakdown(lv.vol, mid, std::max(1, std::min(reps, 5)));
        where.add({lv.label, fmt("%g", mid), fmt("%lld", static_cast<long long>(b.samples)),
                   fmt("%.3f", b.generate_ms), fmt("%.3f", b.project_ms), fmt("%.3f", b.generate_ms + b.project_ms),
                   fmt("%.3f", b.two_stage_ms), fmt("%.3f", b.pipeline_ms)});
    }
    r.table(times);
    if (!fe_info.empty()) r.note("FE: " + fe_info + ".");
    r.note("Sizes and memory, mean per isosurface (IS: 32-byte points; MC: float xyz + float normals + uint32 "
           "indices):");
    r.table(sizes);
    r.note("Where iso-splatting's time goes (median isovalue, single thread): the sampling kernel "
           "(sample_active_cells) and the approximate projection (project_sample) as plain loops over "
           "buffers reused across repetitions; the two-stage pipeline (generate | project, 88-byte samples "
           "between the stages, as the piped commands run); the fused pipeline (the IS column above):");
    r.table(where);
}

void run_threads(const BenchOptions& o, Report& r) {
    r.section("Threads: iso-splatting with 1 and 2 threads (identical output required)");
    std::vector<LoadedVolume> vols = load_volumes(o, r);
    auto largest = std::max_element(vols.begin(), vols.end(), [](const LoadedVolume& a, const LoadedVolume& b) {
        return a.vol.grid.voxel_count() < b.vol.grid.voxel_count();
    });
    const LoadedVolume& lv = *largest;
    const std::vector<double> isos = pick_isovalues(lv.vol, std::min(o.isovalues, 4));
    const int reps = o.reps;
    r.note(fmt("%s (%s, %s), %zu isovalues x %d repetitions; approximate projection into memory. The machine "
               "has %s.",
               lv.label.c_str(), dims_str(lv.vol.grid).c_str(), to_string(lv.vol.type), isos.size(), reps,
               machine_description().c_str()));
    Table t;
    t.header = {"iso", "points", "1 thread ms", "2 threads ms", "speedup", "identical"};
    double sum1 = 0, sum2 = 0;
    bool all_same = true;
    const VolumeView view = lv.vol.view();
    for (double iso : isos) {
        double ms[2] = {0, 0};
        std::vector<PointRecord> out[2];
        for (int rep = 0; rep < reps; ++rep)
            for (int ti = 0; ti < 2; ++ti) {
                CollectSink s;
                Stopwatch sw;
                run_isosplat(view, iso, Projection::approx, SamplingParams{}, s, RunOptions{ti + 1});
                ms[ti] += sw.ms();
                if (rep == 0) out[ti] = std::move(s.points);
            }
        ms[0] /= reps;
        ms[1] /= reps;
        sum1 += ms[0];
        sum2 += ms[1];
        const bool same = out[0].size() == out[1].size() &&
                          (out[0].empty() ||
                           std::memcmp(out[0].data(), out[1].data(), out[0].size() * sizeof(PointRecord)) == 0);
        all_same = all_same && same;
        t.add({fmt("%g", iso), fmt("%zu", out[0].size()), fmt("%.3f", ms[0]), fmt("%.3f", ms[1]),
               ms[1] > 0 ? fmt("%.2f", ms[0] / ms[1]) : "-", same ? "yes" : "NO"});
    }
    const double n = static_cast<double>(isos.size());
    t.add({"mean", "", fmt("%.3f", sum1 / n), fmt("%.3f", sum2 / n), sum2 > 0 ? fmt("%.2f", sum1 / sum2) : "-",
           all_same ? "yes" : "NO"});
    r.table(t);
}

}  // namespace meshless::bench
