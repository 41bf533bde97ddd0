// meshless-bench ooc: the numbers ("bigger than RAM"; dissertation sections 3.5 Table 3.1
// and 3.6): brick-store conversion throughput and compression per dataset; out-of-core paradigm (C)
// from a brick store whose bricks are in the page cache vs the in-memory path on the same volume;
// paradigm (A) (sample store, span-space query) vs a full paradigm-(C) pass vs marching cubes on the
// lung-sized volume (LIDC2 upsampled x2, 511x511x265); threads and MPI ranks of the CLI; peak
// resident memory of `meshless isosurface big.mlb --memory 256M` on a >= 4 GiB volume made by
// `meshless synth --upsample 8` (measured with /usr/bin/time -v, skipped when it is absent).
// Everything it writes goes to a scratch folder (--scratch, default the system temp folder),
// removed at the end unless --keep. Child commands are the `meshless` binary (BenchOptions::meshless).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "bench/bench_common.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/marching_cubes.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_converter.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/brick_store.hpp"
#include "stream/mpi_backend.hpp"
#include "ooc/sample_store.hpp"
#include "ooc/sample_store_writer.hpp"
#include "ooc/slice_source.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"
#include "stream/project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/sample_store_source.hpp"

namespace meshless::bench {

namespace {

namespace fs = std::filesystem;

constexpr double kThroughputTarget = 0.5;     // out-of-core >= 50% of the in-memory path
constexpr double kSpeedupTarget = 10.0;       // paradigm A >= 10x a full C pass ...
constexpr double kSparseActive = 5.0;         // ... for isovalues with < 5% active cells
constexpr double kOverheadTargetMiB = 64.0;   // peak RSS <= budget + 64 MiB
constexpr std::uint64_t kBudget = 256ull << 20;
constexpr double kMiB = 1024.0 * 1024.0;

// ---- small helpers ----------------------------------------------------------------------------

std::string dims_str(const GridSpec& g) {
    return fmt("%lldx%lldx%lld", static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]),
               static_cast<long long>(g.dims[2]));
}

std::int64_t cell_count(const GridSpec& g) {
    return std::max<std::int64_t>(0, g.dims[0] - 1) * std::max<std::int64_t>(0, g.dims[1] - 1) *
           std::max<std::int64_t>(0, g.dims[2] - 1);
}

std::uint64_t bytes_of(const fs::path& p) {
    std::error_code ec;
    const auto n = fs::file_size(p, ec);
    return ec ? 0 : n;
}

std::uint64_t free_bytes(const fs::path& p) {
    std::error_code ec;
    const fs::space_info s = fs::space(p, ec);
    return ec ? 0 : s.available;
}

bool same_bytes(const fs::path& a, const fs::path& b) {
    if (bytes_of(a) != bytes_of(b) || bytes_of(a) == 0) return false;
    std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
    std::vector<char> ba(1 << 20), bb(1 << 20);
    while (fa && fb) {
        fa.read(ba.data(), static_cast<std::streamsize>(ba.size()));
        fb.read(bb.data(), static_cast<std::streamsize>(bb.size()));
        if (fa.gcount() != fb.gcount() || std::memcmp(ba.data(), bb.data(), static_cast<std::size_t>(fa.gcount())) != 0)
            return false;
    }
    return true;
}

/// MemTotal of /proc/meminfo in bytes (0 when unknown).
double mem_total() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    double kb = 0;
    while (in >> key) {
        if (key == "MemTotal:") {
            in >> kb;
            return kb * 1024.0;
        }
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    }
    return 0;
}

bool command_exists(const std::string& name) {
    const std::string cmd = "command -v " + shell_quote(name) + " >/dev/null 2>&1";
    const int st = std::system(cmd.c_str());
    return st != -1 && WIFEXITED(st) && WEXITSTATUS(st) == 0;
}

struct Proc {
    int code = -1;
    double ms = 0;
    std::string err;  ///< its stderr
};

/// Runs a shell command line with stdin/stdout on /dev/null and stderr captured; wall time.
Proc run_shell(const std::string& cmd, const fs::path& errfile) {
    const std::string full = "( " + cmd + " ) </dev/null >/dev/null 2>" + shell_quote(errfile.string());
    Proc p;
    Stopwatch sw;
    const int st = std::system(full.c_str());
    p.ms = sw.ms();
    p.code = st == -1 ? -1 : WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    p.err = read_file_bytes(errfile);
    return p;
}

std::string first_line(const std::string& s) {
    const auto nl = s.find('\n');
    return nl == std::string::npos ? s : s.substr(0, nl);
}

/// Best (smallest) of several wall times.
struct Best {
    double ms = std::numeric_limits<double>::infinity();
    void add(double t) { ms = std::min(ms, t); }
};

/// Counts the records of the batches it receives (samples or points) and drops them.
class CountSink final : public Sink {
public:
    PayloadSet takes() const override { return {Payload::samples, Payload::points}; }
    void consume(Batch&& b) override { n += b.count(); }
    std::uint64_t n = 0;
};

/// The scratch folder of one run: <root>/meshless-bench-ooc-<pid>, removed unless kept.
struct OocScratch {
    fs::path path;
    bool keep = false;
    OocScratch(const std::string& root, bool keep_it) : keep(keep_it) {
        path = fs::path(root.empty() ? fs::temp_directory_path().string() : root) /
               ("meshless-bench-ooc-" + std::to_string(::getpid()));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~OocScratch() {
        if (keep) return;
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    OocScratch(const OocScratch&) = delete;
    OocScratch& operator=(const OocScratch&) = delete;
    fs::path operator/(const std::string& name) const { return path / name; }
};

/// K isovalues evenly spread over the value range (not the histogram), integer types snapped to x.5.
std::vector<double> range_isovalues(const Volume& v, int k) {
    const auto [lo, hi] = v.value_range();
    std::vector<double> out;
    if (!(hi > lo)) return out;
    const bool integer = v.type != SampleType::f32;
    for (int i = 0; i < k; ++i) {
        double x = lo + (hi - lo) * (i + 1) / (k + 1);
        if (integer) {
            if (hi - lo < 1) break;
            x = std::clamp(std::floor(x) + 0.5, lo + 0.5, hi - 0.5);
        }
        if (out.empty() || std::abs(out.back() - x) > 1e-9) out.push_back(x);
    }
    return out;
}

// ---- the lung-sized volume --------------------------------------------------------------------

/// The volume of the throughput, A-vs-C and threads sections: in memory and as a brick store.
struct Lung {
    std::string label;
    Volume vol;
    fs::path store;      ///< brick store of the same samples
    double store_s = 0;  ///< its conversion time
};

// ---- 1. conversion ----------------------------------------------------------------------------

struct ConvSpec {
    std::string label, file;
    std::function<std::unique_ptr<SliceSource>()> open;
};

struct ConvOut {
    std::string label;
    fs::path store;
    double seconds = 0;  ///< best conversion time including opening the input
};

/// Converts each dataset (best of reps), prints the table, and returns each store.
std::vector<ConvOut> run_conversion(const std::vector<ConvSpec>& specs, int reps,
                                                             const OocScratch& scratch, Report& r) {
    const ConvertParams params;  // the CLI defaults (brick 32, zstd level 1; see cli/cmd_convert.cpp)
    r.note(fmt("Default parameters: brick edge %u cells (+1 ghost voxel), zstd level %d, 1 thread. Best of %d. "
               "convert MB/s: voxel bytes / time of convert_to_brick_store (slab reads, compression, spool, "
               "Morton-order copy, fsync); with open: including opening the input (formats that are not raw/NRRD/"
               "MetaImage are read whole there; for synth, the upsampling is inside the conversion). decode MB/s: "
               "read + CRC + decompress every brick, file in the page cache.",
               params.brick_edge, params.zstd_level, reps));
    Table t;
    t.header = {"dataset", "dims", "type", "raw MB", "store MB", "ratio", "convert MB/s", "with open MB/s",
                "decode MB/s", "bricks"};
    std::vector<ConvOut> out;
    for (const ConvSpec& s : specs) {
        std::fprintf(stderr, "bench ooc: converting %s...\n", s.label.c_str());
        const fs::path dst = scratch / s.file;
        Best conv, total;
        ConvertStats st;
        GridSpec grid;
        SampleType type = SampleType::u8;
        try {
            for (int rep = 0; rep < reps; ++rep) {
                Stopwatch sw;
                auto src = s.open();
                st = convert_to_brick_store(*src, dst.string(), params);
                total.add(sw.ms());
                conv.add(st.seconds * 1e3);
                grid = src->grid();
                type = src->type();
            }
        } catch (const std::exception& e) {
            r.note(s.label + ": conversion failed: " + e.what());
            continue;
        }
        Best dec;
        std::uint64_t bricks = 0;
        {
            const auto store = BrickStore::open(dst.string());
            bricks = store->bricks().size();
            std::vector<std::byte> buf;
            for (int rep = 0; rep < reps; ++rep) {
                Stopwatch sw;
                for (std::size_t i = 0; i < store->bricks().size(); ++i) store->read_brick(i, buf);
                dec.add(sw.ms());
            }
        }
        const double mb = static_cast<double>(st.input_bytes) / 1e6;
        t.add({s.label, dims_str(grid), to_string(type), fmt("%.1f", mb), fmt("%.2f", st.output_bytes / 1e6),
               st.output_bytes ? fmt("%.2f", static_cast<double>(st.input_bytes) / static_cast<double>(st.output_bytes))
                               : "-",
               fmt("%.0f", mb / (conv.ms / 1e3)), fmt("%.0f", mb / (total.ms / 1e3)), fmt("%.0f", mb / (dec.ms / 1e3)),
               fmt("%llu", static_cast<unsigned long long>(bricks))});
        out.push_back({s.label, dst, total.ms / 1e3});
    }
    r.table(t);
    return out;
}

// ---- 2. out-of-core throughput ----------------------------------------------------------------

void run_throughput(const Lung& lung, const std::vector<double>& isos, int reps, Report& r) {
    r.section("Out-of-core throughput: paradigm (C) from the brick store (page cache warm) vs in memory");
    const auto store = BrickStore::open(lung.store.string());
    const BrickIndex index(*store);
    const VolumeView view = lung.vol.view();
    r.note(fmt("%s (%s, %s, %.1f MB in memory; store %.1f MB). Same %zu isovalues, 1 thread, approximate projection, "
               "points kept in memory (CollectSink), best of %d. in memory: run_isosplat on the Volume. "
               "store, fresh cache: what `meshless isosurface vol.mlb --memory 256M` does per isovalue (brick "
               "interval tree, a new 256 MiB BrickCache, every active brick read from the page cache, CRC-checked "
               "and decompressed). store, warm cache: the same with the decompressed bricks already cached. "
               "Throughput = in-memory time / store time (target >= %.1f).",
               lung.label.c_str(), dims_str(lung.vol.grid).c_str(), to_string(lung.vol.type),
               static_cast<double>(lung.vol.bytes.size()) / 1e6, bytes_of(lung.store) / 1e6, isos.size(), reps,
               kThroughputTarget));
    {  // warm-up: page in the store and the volume
        std::vector<std::byte> buf;
        for (std::size_t i = 0; i < store->bricks().size(); ++i) store->read_brick(i, buf);
        CollectSink s(true);
        run_isosplat(view, isos[isos.size() / 2], Projection::approx, SamplingParams{}, s, RunOptions{1});
    }
    BrickCache warm(*store, std::max<std::uint64_t>(kBudget, 4 * lung.vol.bytes.size()));
    Table t;
    t.header = {"iso", "active bricks", "points", "in memory ms", "store ms (fresh cache)", "store ms (warm cache)",
                "throughput fresh", "throughput warm", "same points"};
    double sum_mem = 0, sum_fresh = 0, sum_warm = 0;
    bool all_same = true;
    for (double iso : isos) {
        Best mem, fresh, cached;
        std::size_t n_mem = 0, n_ooc = 0, n_active = 0;
        {  // fill the warm cache with this isovalue's bricks (not timed)
            CountSink s;
            run_isosplat_bricks(*store, warm, index.active(iso), iso, Projection::approx, SamplingParams{}, s, {1});
        }
        for (int rep = 0; rep < reps; ++rep) {
            {
                CollectSink s(true);
                Stopwatch sw;
                run_isosplat(view, iso, Projection::approx, SamplingParams{}, s, RunOptions{1});
                mem.add(sw.ms());
                n_mem = s.size();
            }
            {
                CollectSink s(true);
                Stopwatch sw;
                BrickCache cache(*store, kBudget);
                std::vector<std::size_t> active = index.active(iso);
                n_active = active.size();
                run_isosplat_bricks(*store, cache, std::move(active), iso, Projection::approx, SamplingParams{}, s, {1});
                fresh.add(sw.ms());
                n_ooc = s.size();
            }
            {
                CollectSink s(true);
                Stopwatch sw;
                run_isosplat_bricks(*store, warm, index.active(iso), iso, Projection::approx, SamplingParams{}, s, {1});
                cached.add(sw.ms());
            }
        }
        sum_mem += mem.ms;
        sum_fresh += fresh.ms;
        sum_warm += cached.ms;
        all_same = all_same && n_mem == n_ooc;
        t.add({fmt("%g", iso), fmt("%zu", n_active), fmt("%zu", n_mem), fmt("%.1f", mem.ms), fmt("%.1f", fresh.ms),
               fmt("%.1f", cached.ms), fmt("%.2f", mem.ms / fresh.ms), fmt("%.2f", mem.ms / cached.ms),
               n_mem == n_ooc ? "yes" : "NO"});
    }
    const double q = sum_mem / sum_fresh;
    t.add({"all", "", "", fmt("%.1f", sum_mem), fmt("%.1f", sum_fresh), fmt("%.1f", sum_warm),
           fmt("%.2f %s", q, q >= kThroughputTarget ? "PASS" : "FAIL"), fmt("%.2f", sum_mem / sum_warm),
           all_same ? "yes" : "NO"});
    r.table(t);
    const double vol_mb = static_cast<double>(lung.vol.bytes.size()) / 1e6 * static_cast<double>(isos.size());
    r.note(fmt("Volume bytes per second over the %zu isovalues: in memory %.0f MB/s, store with a fresh cache %.0f MB/s, "
               "warm cache %.0f MB/s. The store pays for brick decompression, the ghost layer (bricks of 33^3 voxels "
               "for 32^3 cells) and per-brick pipeline work; it skips bricks the isosurface does not cross.",
               isos.size(), vol_mb / (sum_mem / 1e3), vol_mb / (sum_fresh / 1e3), vol_mb / (sum_warm / 1e3)));
}

// ---- 3. paradigm A vs C vs marching cubes -----------------------------------------------------

void run_paradigms(const Lung& lung, const std::vector<double>& isos, int reps, const OocScratch& scratch,
                   const std::string& exe, double mlb_build_s, Report& r) {
    r.section("Paradigm (A) vs paradigm (C) vs marching cubes (Table 3.1)");
    const fs::path mls = scratch / "lung.mls";
    const auto bstore = BrickStore::open(lung.store.string());
    const BrickIndex index(*bstore);
    std::fprintf(stderr, "bench ooc: building the paradigm-(A) sample store...\n");
    SampleStoreBuildStats bs;
    double mls_s = 0;
    {
        Stopwatch sw;
        bs = write_sample_store(*bstore, mls.string());
        mls_s = sw.ms() / 1e3;
    }
    const auto sstore = SampleStore::open(mls.string());
    const double raw = static_cast<double>(lung.vol.bytes.size());
    const std::int64_t cells = cell_count(lung.vol.grid);
    Table sz;
    sz.header = {"paradigm", "file", "size MB", "size / raw volume", "build s", "made by"};
    sz.add({"(C) brick store", ".mlb", fmt("%.1f", bytes_of(lung.store) / 1e6),
            fmt("%.3f", static_cast<double>(bytes_of(lung.store)) / raw), fmt("%.2f", mlb_build_s),
            "convert / synth (section above)"});
    sz.add({"(A) sample store", ".mls", fmt("%.1f", bytes_of(mls) / 1e6),
            fmt("%.3f", static_cast<double>(bytes_of(mls)) / raw), fmt("%.2f", mls_s),
            "write_sample_store (= generate --all vol.mlb)"});
    r.note(fmt("%s (%s, %s): %lld cells; the sample store files the cell rows of the non-constant cells by span-space "
               "bucket (%llu cells, %llu constant cells, %llu span-space buckets, %u levels%s).",
               lung.label.c_str(), dims_str(lung.vol.grid).c_str(), to_string(lung.vol.type), static_cast<long long>(cells),
               static_cast<unsigned long long>(bs.cells), static_cast<unsigned long long>(bs.constant_cells),
               static_cast<unsigned long long>(bs.buckets), bs.levels, bs.exact_levels ? ", exact" : ""));
    r.table(sz);

    r.note(fmt("%zu isovalues evenly spread over the value range (x.5 for integer data). 1 thread, best of %d, "
               "files in the page cache. A query: SampleStore::query into a counting callback (the samples of the "
               "active cells, read through the span-space index). C generate: run_isosplat_bricks, samples only, "
               "counted (the samples of the same cells, from the .mlb, fresh 256 MiB brick cache). A+proj / C full: "
               "the same followed by the approximate projection into memory (points out). MC: marching_cubes on the "
               "in-memory volume (mesh with normals). CLI: wall time of `meshless extract vol.mls --iso V -o /dev/null` "
               "and `meshless generate vol.mlb --iso V -o /dev/null` (same sample stream format; process start and "
               "store opening included). C every brick: C generate over all bricks (no brick interval tree).",
               isos.size(), reps));
    Table t;
    t.header = {"iso", "active %", "active bricks %", "samples", "A query ms", "C generate ms", "A+proj ms",
                "C full ms", "MC ms", "CLI A ms", "CLI C ms", "C gen/A", "C full/A+proj", "CLI C/A",
                "C every brick ms", "C every/A", "same cells"};
    std::vector<double> sparse_gen, sparse_full, sparse_cli;
    double s_aq = 0, s_cg = 0, s_ap = 0, s_cf = 0, s_mc = 0, s_la = 0, s_lc = 0, s_ce = 0;
    std::vector<double> sparse_every;
    std::vector<std::size_t> all_bricks(bstore->bricks().size());
    for (std::size_t i = 0; i < all_bricks.size(); ++i) all_bricks[i] = i;
    bool all_same = true;
    const VolumeView view = lung.vol.view();
    const fs::path err = scratch / "cli.err";
    std::string cli_fail;
    for (double iso : isos) {
        std::fprintf(stderr, "bench ooc: paradigms at iso %g...\n", iso);
        Best aq, cg, ap, cf, mc, la, lc, ce;
        const std::size_t n_active_bricks = index.active(iso).size();
        std::uint64_t a_n = 0, c_n = 0;
        for (int rep = 0; rep < reps; ++rep) {
            {
                std::uint64_t n = 0;
                Stopwatch sw;
                sstore->query(iso, [&](std::span<const SampleRecord> s) { n += s.size(); });
                aq.add(sw.ms());
                a_n = n;
            }
            {
                CountSink s;
                Stopwatch sw;
                BrickCache cache(*bstore, kBudget);
                run_isosplat_bricks(*bstore, cache, index.active(iso), iso, Projection::approx, SamplingParams{}, s, {1},
                                    PipelineShape::samples_only);
                cg.add(sw.ms());
                c_n = s.n;
            }
            {
                CollectSink s(true);
                Stopwatch sw;
                SampleStoreSource src(*sstore, iso);
                const ProjectStage proj(iso, Projection::approx);
                const Stage* stages[] = {&proj};
                run_pipeline(src, stages, s, {1});
                ap.add(sw.ms());
            }
            {
                CollectSink s(true);
                Stopwatch sw;
                BrickCache cache(*bstore, kBudget);
                run_isosplat_bricks(*bstore, cache, index.active(iso), iso, Projection::approx, SamplingParams{}, s, {1});
                cf.add(sw.ms());
            }
            {  // C without the brick interval tree: every brick decompressed and scanned
                CountSink s;
                Stopwatch sw;
                BrickCache cache(*bstore, kBudget);
                run_isosplat_bricks(*bstore, cache, all_bricks, iso, Projection::approx, SamplingParams{}, s, {1},
                                    PipelineShape::samples_only);
                ce.add(sw.ms());
            }
            {
                Mesh m;
                Stopwatch sw;
                m = marching_cubes(view, iso);
                mc.add(sw.ms());
            }
            const std::string iso_s = fmt("%.17g", iso);
            const Proc pa = run_shell(shell_quote(exe) + " extract " + shell_quote(mls.string()) + " --iso " + iso_s + " -o /dev/null", err);
            const Proc pc = run_shell(shell_quote(exe) + " generate " + shell_quote(lung.store.string()) + " --iso " + iso_s +
                                          " --memory 256M -o /dev/null",
                                      err);
            if (pa.code == 0) la.add(pa.ms);
            else if (cli_fail.empty()) cli_fail = "extract: " + first_line(pa.err);
            if (pc.code == 0) lc.add(pc.ms);
            else if (cli_fail.empty()) cli_fail = "generate: " + first_line(pc.err);
        }
        const double pct = cells > 0 ? 100.0 * static_cast<double>(a_n) / static_cast<double>(cells) : 0;
        const bool cli_ok = std::isfinite(la.ms) && std::isfinite(lc.ms);
        all_same = all_same && a_n == c_n;
        if (pct < kSparseActive) {
            sparse_gen.push_back(cg.ms / aq.ms);
            sparse_full.push_back(cf.ms / ap.ms);
            if (cli_ok) sparse_cli.push_back(lc.ms / la.ms);
            sparse_every.push_back(ce.ms / aq.ms);
        }
        s_aq += aq.ms, s_cg += cg.ms, s_ap += ap.ms, s_cf += cf.ms, s_mc += mc.ms, s_ce += ce.ms;
        if (cli_ok) s_la += la.ms, s_lc += lc.ms;
        t.add({fmt("%g", iso), fmt("%.2f", pct),
               fmt("%.1f", 100.0 * static_cast<double>(n_active_bricks) / static_cast<double>(all_bricks.size())),
               fmt("%llu", static_cast<unsigned long long>(a_n)), fmt("%.2f", aq.ms), fmt("%.2f", cg.ms),
               fmt("%.2f", ap.ms), fmt("%.2f", cf.ms), fmt("%.2f", mc.ms), cli_ok ? fmt("%.1f", la.ms) : "-",
               cli_ok ? fmt("%.1f", lc.ms) : "-", fmt("%.1f", cg.ms / aq.ms), fmt("%.1f", cf.ms / ap.ms),
               cli_ok ? fmt("%.1f", lc.ms / la.ms) : "-", fmt("%.2f", ce.ms), fmt("%.1f", ce.ms / aq.ms),
               a_n == c_n ? "yes" : "NO"});
    }
    const double n = static_cast<double>(isos.size());
    t.add({"mean", "", "", "", fmt("%.2f", s_aq / n), fmt("%.2f", s_cg / n), fmt("%.2f", s_ap / n),
           fmt("%.2f", s_cf / n), fmt("%.2f", s_mc / n), s_la > 0 ? fmt("%.1f", s_la / n) : "-",
           s_lc > 0 ? fmt("%.1f", s_lc / n) : "-", fmt("%.1f", s_cg / s_aq), fmt("%.1f", s_cf / s_ap),
           s_la > 0 ? fmt("%.1f", s_lc / s_la) : "-", fmt("%.2f", s_ce / n), fmt("%.1f", s_ce / s_aq),
           all_same ? "yes" : "NO"});
    r.table(t);
    if (!cli_fail.empty()) r.note("CLI runs failed: " + cli_fail);
    r.note(fmt("Per isovalue, mean: A query %.2f ms, A+proj %.2f ms, C full pass %.2f ms, marching cubes %.2f ms "
               "(A+proj / MC = %.2f, C full / MC = %.2f).",
               s_aq / n, s_ap / n, s_cf / n, s_mc / n, s_ap / s_mc, s_cf / s_mc));
    auto verdict = [&](const char* what, const std::vector<double>& v) {
        if (v.empty()) return fmt("%s: no isovalue with < %.0f%% active cells", what, kSparseActive);
        const double lo = *std::min_element(v.begin(), v.end());
        double gm = 0;
        for (double x : v) gm += std::log(x);
        gm = std::exp(gm / static_cast<double>(v.size()));
        return fmt("%s: min %.1fx, geometric mean %.1fx over %zu isovalues: %s", what, lo, gm, v.size(),
                   lo >= kSpeedupTarget ? "PASS" : "FAIL");
    };
    r.note(fmt("Target: paradigm (A) >= %.0fx faster than a full paradigm-(C) pass for isovalues with < %.0f%% active "
               "cells.",
               kSpeedupTarget, kSparseActive));
    r.note("- " + verdict("extraction, samples out (C generate / A query)", sparse_gen));
    r.note("- " + verdict("with projection, points out (C full / A+proj)", sparse_full));
    r.note("- " + verdict("command line (generate vol.mlb / extract vol.mls)", sparse_cli));
    r.note("- for reference, against a C pass that does not use the brick interval tree (every brick decompressed "
           "and scanned, samples out): " + verdict("C every brick / A query", sparse_every));
}

// ---- 4. threads and ranks ---------------------------------------------------------------------

/// The volume a threads/ranks table runs on.
struct ScalingCase {
    std::string label;     ///< e.g. "LIDC2 x2 (...) 511x511x265"
    fs::path store;
    double iso = 0;        ///< the isovalue timed
    double empty_iso = 0;  ///< an isovalue above the maximum (no active brick): start-up cost alone
    std::string why;       ///< how iso was chosen
};

/// 1 vs 2 threads and mpirun -np 1 vs 2 of `meshless isosurface STORE --iso V -o FILE`: wall time of
/// the whole command, best of reps, outputs compared byte for byte; PLYs removed afterwards.
void run_threads_ranks(const ScalingCase& c, int reps, bool mpi, const OocScratch& scratch, const std::string& exe,
                       Report& r) {
    const fs::path err = scratch / "threads.err";
    const std::string head = shell_quote(exe) + " isosurface " + shell_quote(c.store.string()) + " --memory 256M";
    const std::string base = head + fmt(" --iso %.17g", c.iso);
    const std::string root_flag = ::geteuid() == 0 ? " --allow-run-as-root" : "";
    const std::string mpirun = "mpirun" + root_flag + " --oversubscribe -np ";
    struct Run {
        std::string label, cmd;
        fs::path out;  ///< empty: output not compared
        bool mpi = false;
    };
    std::vector<Run> runs = {
        {"--threads 1", base + " --threads 1 -o " + shell_quote((scratch / "t1.ply").string()), scratch / "t1.ply"},
        {"--threads 2", base + " --threads 2 -o " + shell_quote((scratch / "t2.ply").string()), scratch / "t2.ply"},
    };
    if (mpi) {
        for (int np : {1, 2}) {
            const fs::path out = scratch / fmt("np%d.ply", np);
            runs.push_back({fmt("mpirun -np %d", np),
                            mpirun + std::to_string(np) + " " + base + " --threads 1 -o " + shell_quote(out.string()), out, true});
        }
        for (int np : {1, 2})
            runs.push_back({fmt("mpirun -np %d, no active brick (start-up cost)", np),
                            mpirun + std::to_string(np) + " " + head + fmt(" --iso %.17g", c.empty_iso) +
                                " --threads 1 -o " + shell_quote((scratch / "empty.ply").string()),
                            {}, true});
    }
    r.note(fmt("%s, iso %g (%s); wall time of the whole command (process start, store open, brick interval tree, "
               "output PLY written), best of %d; threads and ranks speedups against --threads 1 and mpirun -np 1. "
               "Outputs compared byte for byte with the 1-thread run.",
               c.label.c_str(), c.iso, c.why.c_str(), reps));
    Table t;
    t.header = {"run", "wall ms", "speedup", "output MB", "identical"};
    double base_ms = 0, np1_ms = 0;
    std::string fails;
    for (const Run& run : runs) {
        std::fprintf(stderr, "bench ooc: %s...\n", run.label.c_str());
        Best b;
        std::string fail;
        for (int rep = 0; rep < reps; ++rep) {
            const Proc p = run_shell(run.cmd, err);
            if (p.code != 0) {
                fail = fmt("exit %d: ", p.code) + first_line(p.err);
                break;
            }
            b.add(p.ms);
        }
        if (!fail.empty()) {
            t.add({run.label, "-", "-", "-", "failed"});
            fails += run.label + " failed (" + fail + "). ";
            continue;
        }
        if (run.label == "--threads 1") base_ms = b.ms;
        if (run.label == "mpirun -np 1") np1_ms = b.ms;
        if (run.out.empty()) {
            t.add({run.label, fmt("%.0f", b.ms), "", "", ""});
            continue;
        }
        const double ref = run.mpi ? np1_ms : base_ms;
        const bool same = run.out == runs[0].out || same_bytes(runs[0].out, run.out);
        t.add({run.label, fmt("%.0f", b.ms), ref > 0 ? fmt("%.2f", ref / b.ms) : "-",
               fmt("%.1f", bytes_of(run.out) / 1e6), same ? "yes" : "NO"});
    }
    r.table(t);
    if (!fails.empty()) r.note(fails);
    if (!mpi) r.note("MPI runs skipped (--quick, no mpirun, or meshless built without MPI).");
    std::error_code ec;
    for (const Run& run : runs)
        if (!run.out.empty()) fs::remove(run.out, ec);
    fs::remove(scratch / "empty.ply", ec);
}

// ---- 5. peak resident memory ------------------------------------------------------------------

struct TimeV {
    bool ok = false;
    double rss_kib = 0, wall_s = 0;
    long long points = -1, active = -1;
    std::string err;
};

/// Runs `/usr/bin/time -v -o TIMEFILE cmd`; parses max RSS and wall time, and the isosurface --stats
/// line ("N active cells, M points") from the command's stderr.
TimeV time_v(const std::string& cmd, const OocScratch& scratch) {
    const fs::path tf = scratch / "time.txt", ef = scratch / "time.err";
    const Proc p = run_shell("/usr/bin/time -v -o " + shell_quote(tf.string()) + " " + cmd, ef);
    TimeV t;
    t.err = first_line(p.err);
    if (p.code != 0) return t;
    const std::string tv = read_file_bytes(tf);
    if (const auto k = tv.find("Maximum resident set size (kbytes):"); k != std::string::npos)
        t.rss_kib = std::strtod(tv.c_str() + k + 35, nullptr);
    t.wall_s = p.ms / 1e3;
    if (const auto k = p.err.find(" active cells, "); k != std::string::npos) {
        std::size_t b = k;
        while (b > 0 && std::isdigit(static_cast<unsigned char>(p.err[b - 1]))) --b;
        t.active = std::strtoll(p.err.c_str() + b, nullptr, 10);
        t.points = std::strtoll(p.err.c_str() + k + 15, nullptr, 10);
    }
    t.ok = t.rss_kib > 0;
    return t;
}

void run_peak_rss(const BenchOptions& o, const Lung& lung, const OocScratch& scratch, const std::string& exe,
                  const std::string& lidc_path, bool mpi, Report& r) {
    r.section("Peak resident memory: meshless isosurface --memory on a volume of >= 4 GiB");
    if (!fs::exists("/usr/bin/time")) {
        r.note("/usr/bin/time not found (apt-get install time): peak-memory measurement skipped.");
        return;
    }
    fs::path big = lung.store;
    std::string label = lung.label + " store (--quick: not the >= 4 GiB volume)";
    std::uint64_t budget = 4ull << 20;  // --quick: smaller than the LIDC2 store's 11.5 MB of bricks
    double iso = 100.5;
    if (!o.quick) {
        if (lidc_path.empty()) {
            r.note("LIDC2 not found under the data folder: the >= 4 GiB volume cannot be made; skipped.");
            return;
        }
        const double raw_guess = 2041.0 * 2041.0 * 1057.0;
        if (static_cast<double>(free_bytes(scratch.path)) < raw_guess / 4 + 512 * kMiB) {
            r.note(fmt("Scratch folder %s has %s free; the 4.4 GB volume's store needs about %s: skipped.",
                       scratch.path.c_str(), bytes_str(static_cast<double>(free_bytes(scratch.path))).c_str(),
                       bytes_str(raw_guess / 4 + 512 * kMiB).c_str()));
            return;
        }
        big = scratch / "big.mlb";
        std::fprintf(stderr, "bench ooc: meshless synth --upsample 8 (about 4.4 GB of voxels)...\n");
        const TimeV s = time_v(shell_quote(exe) + " synth --upsample 8 " + shell_quote(lidc_path) + " -o " + shell_quote(big.string()), scratch);
        if (!s.ok) {
            r.note("meshless synth --upsample 8 failed: " + s.err);
            return;
        }
        const auto st = BrickStore::open(big.string());
        const GridSpec& g = st->info().grid;
        const double vox = static_cast<double>(g.voxel_count()) * static_cast<double>(sample_size(st->info().type));
        r.note(fmt("`meshless synth --upsample 8 LIDC2.vti -o big.mlb` (trilinear): %s %s = %s of voxels (%.2f GiB) -> "
                   "store %s (ratio %.2f), %.1f s (%.0f MB/s), peak RSS %s.",
                   dims_str(g).c_str(), to_string(st->info().type), bytes_str(vox).c_str(), vox / (kMiB * 1024),
                   bytes_str(static_cast<double>(bytes_of(big))).c_str(), vox / static_cast<double>(bytes_of(big)),
                   s.wall_s, vox / 1e6 / s.wall_s, bytes_str(s.rss_kib * 1024).c_str()));
        label = fmt("LIDC2 x8 %s", dims_str(g).c_str());
        budget = kBudget;
        iso = 100.5;
    } else {
        const std::vector<double> mid = range_isovalues(lung.vol, 1);
        iso = mid.empty() ? 0.5 : mid[0];
    }
    const std::string mem = fmt(" --memory %lluM", static_cast<unsigned long long>(budget >> 20));
    const std::string iso_s = fmt(" --iso %.17g", iso);
    const fs::path ply = scratch / "big.ply";
    Table t;
    t.header = {"command", "budget", "points", "wall s", "max RSS", "RSS - budget", "held points", "fixed overhead",
                "<= 64 MiB"};
    auto row = [&](const std::string& what, const TimeV& v, double bud, bool held) {
        if (!v.ok) {
            t.add({what, bytes_str(bud), "-", "-", "failed", "-", "-", "-", "-"});
            r.note(what + " failed: " + v.err);
            return;
        }
        const double rss = v.rss_kib * 1024.0;
        const double held_b = held && v.points >= 0 ? static_cast<double>(v.points) * 32.0 : 0;
        const double over = (rss - bud - held_b) / kMiB;
        t.add({what, bud > 0 ? bytes_str(bud) : "-", v.points >= 0 ? fmt("%lld", v.points) : "-", fmt("%.2f", v.wall_s),
               bytes_str(rss), bud > 0 ? fmt("%.1f MiB", (rss - bud) / kMiB) : "-", held ? bytes_str(held_b) : "0",
               fmt("%.1f MiB", over),
               held ? "n/a (output held)" : bud > 0 ? (over <= kOverheadTargetMiB ? "PASS" : "FAIL") : ""});
    };
    std::fprintf(stderr, "bench ooc: peak RSS runs on %s...\n", label.c_str());
    row("meshless --version (binary + libraries)", time_v(shell_quote(exe) + " --version", scratch), 0, false);
    const std::string cmd = shell_quote(exe) + " isosurface " + shell_quote(big.string()) + iso_s + " --stats";
    const TimeV dn = time_v(cmd + mem + " -o /dev/null", scratch);
    row("isosurface" + mem + " -o /dev/null", dn, static_cast<double>(budget), true);
    const double ply_bytes = dn.points > 0 ? static_cast<double>(dn.points) * 32.0 + 4096 : 0;
    if (static_cast<double>(free_bytes(scratch.path)) < ply_bytes + 256 * kMiB) {
        r.note(fmt("Not enough free space in %s for the %s PLY: -o FILE runs skipped.", scratch.path.c_str(),
                   bytes_str(ply_bytes).c_str()));
    } else {
        row("isosurface" + mem + " -o FILE.ply", time_v(cmd + mem + " -o " + shell_quote(ply.string()), scratch),
            static_cast<double>(budget), false);
        std::error_code ec;
        fs::remove(ply, ec);
        if (!o.quick) {
            row("isosurface --memory 64M -o FILE.ply", time_v(cmd + " --memory 64M -o " + shell_quote(ply.string()), scratch),
                64.0 * kMiB, false);
            fs::remove(ply, ec);
        }
    }
    r.note(fmt("%s, iso %g, 1 thread; `/usr/bin/time -v`, maximum resident set size. fixed overhead = max RSS - "
               "budget - points held in memory (32 bytes each). Target: fixed overhead <= %.0f MiB with the output "
               "streamed to a file.",
               label.c_str(), iso, kOverheadTargetMiB));
    r.table(t);
    r.note("-o /dev/null is a device: a PLY header holds the vertex count, and a device cannot seek back to patch "
           "it, so PlySink keeps every point in memory and writes at the end (as for stdout and FIFOs); its peak "
           "is budget + overhead + the held points, which take up to twice 32 bytes per point while the held "
           "array grows (geometric growth: the old and new arrays coexist while it is copied), so the "
           "\"fixed overhead\" of that row is not fixed. -o FILE.ply streams the points to the file (the count is "
           "patched at the end), so its peak is budget + a fixed overhead whatever the size of the surface. The "
           "overhead is the binary and its shared libraries (first row), the brick interval tree and index (64 "
           "bytes per brick), zstd contexts, the bricks in use by the running thread beyond the cache, and the "
           "batches in flight.");
    if (o.quick) return;
    // threads and ranks where the work dominates the start-up: the big volume
    const double need = 4 * ply_bytes + 512 * kMiB;
    if (dn.points <= 0 || static_cast<double>(free_bytes(scratch.path)) < need) {
        r.note(fmt("Threads and ranks on the big volume skipped (needs %s free for four PLYs).", bytes_str(need).c_str()));
        return;
    }
    r.note("Threads and MPI ranks on this volume (work large enough to dominate the start-up):");
    const auto st = BrickStore::open(big.string());
    run_threads_ranks({label, big, iso, st->info().value_max + 1, "as above"}, 2, mpi, scratch, exe, r);
}

}  // namespace

bool ooc_scratch_has_room(const BenchOptions& o) {
    const std::string root = o.scratch_dir.empty() ? fs::temp_directory_path().string() : o.scratch_dir;
    return free_bytes(root) >= kOocScratchRoom;
}

void run_ooc(const BenchOptions& o, Report& r) {
    r.section("Out of core: brick stores, paradigms (A) and (C), threads and ranks, peak memory");
    OocScratch scratch(o.scratch_dir, o.keep);
    const std::string exe = o.meshless;
    const int reps = o.quick ? 1 : std::clamp(o.reps, 1, 3);
    // the executable runs under mpirun when its MPI plugin sits beside it (stream/mpi_backend.hpp)
    const bool mpi_built = std::filesystem::exists(std::filesystem::path(exe).parent_path() / meshless::kMpiPluginFile);
    const bool mpi = !o.quick && mpi_built && command_exists("mpirun");
    r.note(fmt("Machine: %s, %s RAM; scratch folder %s (%s free)%s; MPI %s. Single-threaded unless stated; ratios "
               "are measured in this run.",
               machine_description().c_str(), bytes_str(mem_total()).c_str(), scratch.path.c_str(),
               bytes_str(static_cast<double>(free_bytes(scratch.path))).c_str(), o.keep ? ", kept (--keep)" : "",
               mpi ? "used (mpirun found)" : mpi_built ? "not used" : "not built in"));

    // datasets
    std::error_code ec;
    auto data = [&](const std::string& rel) {
        const fs::path p = fs::path(o.data_dir) / rel;
        return fs::exists(p, ec) ? p.string() : std::string();
    };
    const std::string lidc = data("vtkjs_LIDC2/LIDC2.vti");
    std::vector<ConvSpec> specs;
    std::string missing;
    for (const auto& [label, rel, file] : {std::tuple<const char*, const char*, const char*>{"LIDC2 chest CT", "vtkjs_LIDC2/LIDC2.vti", "lidc2.mlb"},
                                           {"tooth", "tooth/tooth_103x94x161_uint8.raw", "tooth.mlb"},
                                           {"headsq quarter", "vtk_headsq/quarter.nhdr", "headsq.mlb"},
                                           {"neghip", "neghip/neghip_64x64x64_uint8.raw", "neghip.mlb"}}) {
        const std::string p = data(rel);
        if (p.empty()) {
            missing += (missing.empty() ? "" : ", ") + std::string(rel);
            continue;
        }
        specs.push_back({label, file, [p] { return open_slice_source(p); }});
    }
    if (!missing.empty()) r.note("not found under '" + o.data_dir + "': " + missing);

    Lung lung;
    std::optional<Volume> lidc_vol;  // the synth source must outlive the conversion
    if (!lidc.empty()) {
        lidc_vol = read_volume(lidc);
        if (!o.quick) {
            const Volume* v = &*lidc_vol;
            specs.push_back({"LIDC2 x2 (synth, trilinear)", "lung.mlb",
                             [v] { return make_upsampling_source(*v, 2, Upsampling::trilinear, "LIDC2 x2"); }});
        }
    } else {
        // no real data: an analytic float volume stands in for the lung (and there is no 4 GiB volume)
        const std::int64_t n = o.quick ? 48 : 192;
        auto vol = std::make_shared<const Volume>(make_analytic_volume(AnalyticField::gyroid, n));
        specs.push_back({fmt("analytic gyroid %lld^3", static_cast<long long>(n)), "lung.mlb",
                         [vol] { return make_volume_source(*vol, "gyroid"); }});
    }

    r.section("Conversion: brick store throughput and compression per dataset");
    const auto stores = run_conversion(specs, reps, scratch, r);
    if (stores.empty()) {
        r.note("no dataset could be converted: the remaining out-of-core tables are skipped");
        return;
    }
    // the lung: the last spec (LIDC2 x2, or the analytic stand-in); --quick: LIDC2 itself
    const ConvOut* lung_conv = &stores.back();
    if (!lidc.empty() && o.quick)
        for (const ConvOut& c : stores)
            if (c.label == "LIDC2 chest CT") lung_conv = &c;
    lung.label = lung_conv->label;
    lung.store = lung_conv->store;
    std::fprintf(stderr, "bench ooc: loading %s into memory...\n", lung.label.c_str());
    if (!lidc.empty() && o.quick) {
        lung.vol = *lidc_vol;
    } else if (!lidc.empty()) {
        // the in-memory path reads the same samples the store was made from
        auto src = make_upsampling_source(*lidc_vol, 2, Upsampling::trilinear, "LIDC2 x2");
        lung.vol = Volume(src->grid(), src->type());
        src->read_slices(0, src->grid().dims[2], lung.vol.bytes.data());
    } else {
        lung.vol = make_analytic_volume(AnalyticField::gyroid, o.quick ? 48 : 192);
    }
    const double mlb_s = lung_conv->seconds;

    std::vector<double> isos = range_isovalues(lung.vol, o.isovalues);
    if (isos.empty()) {
        r.note(lung.label + ": constant volume, the remaining tables are skipped");
        return;
    }
    run_throughput(lung, isos, reps, r);
    run_paradigms(lung, isos, reps, scratch, exe, mlb_s, r);

    // the isovalue with the most active bricks for the threads/ranks runs
    {
        const auto st = BrickStore::open(lung.store.string());
        const BrickIndex index(*st);
        double best_iso = isos[0];
        std::size_t most = 0;
        for (double iso : isos)
            if (const std::size_t n = index.active(iso).size(); n > most) most = n, best_iso = iso;
        r.section("Threads and MPI ranks: meshless isosurface on the brick store");
        r.note("Machine: " + machine_description() +
               ". mpirun -np 1 runs the single-process code path under mpirun; -np 2 splits the active bricks into "
               "two Morton ranges, rank 0 gathers the points (in rank order) and writes the file. The \"no active "
               "brick\" rows (an isovalue above the maximum) time the start-up alone: mpirun, MPI_Init/Finalize, "
               "store open.");
        run_threads_ranks({lung.label + " " + dims_str(lung.vol.grid), lung.store, best_iso,
                           lung.vol.value_range()[1] + 1, "the isovalue with the most active bricks of the set above"},
                          o.quick ? 1 : 3, mpi, scratch, exe, r);
    }
    run_peak_rss(o, lung, scratch, exe, lidc, mpi, r);
    if (o.keep) r.note("Scratch files kept in " + scratch.path.string() + " (--keep).");
}

}  // namespace meshless::bench
