// Shared pieces of `meshless-bench` (dissertation §3.6: extraction time, memory and frame rate of
// iso-splatting vs marching cubes): options, the report (plain-text tables on stdout, the same
// tables as markdown for bench/RESULTS.md), the machine description, a wall clock, isovalue
// selection over a volume's histogram, and the list of benchmark volumes under the data folder.
//
// Units: times in milliseconds unless a column says otherwise; memory in bytes (printed as MiB/KiB);
// distances in voxels. Nothing here is thread-safe: one Report per bench run, used by one thread.
// Throws IoError when the markdown file cannot be written; cli::UsageError for bad options.
#pragma once
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "kernels/field.hpp"
#include "kernels/grid.hpp"
#include "kernels/point_set.hpp"

namespace meshless::bench {

struct BenchOptions {
    std::string data_dir;     ///< folder holding the shared test data (may not exist)
    std::string bench_dir;    ///< folder holding flying_edges.py and rbf_reference.py
    int reps = 10;            ///< repetitions per isosurface
    int isovalues = 16;       ///< isosurfaces per volume
    bool quick = false;       ///< smoke-test mode: few reps and isovalues, no large volumes
    std::string python = "/usr/bin/python3";  ///< interpreter with vtk (FE baseline) and scipy (fields reference)
    std::string scratch_dir;  ///< ooc section: folder for its stores (empty: the system temp folder)
    bool keep = false;        ///< ooc section: keep the scratch files
    bool with_ooc = false;    ///< "all" includes the ooc section even without kOocScratchRoom free
    std::string meshless;     ///< the `meshless` executable that whole-process rows run (ooc, process)
    std::string work_dir;     ///< process: cache folder for its volumes and point sets (empty: a temp folder)
    int process_reps = 3;     ///< process: best of this many runs per row
    bool large = false;       ///< process: also the 10^8-point splat row
    std::string scattered_sizes;  ///< scattered: point counts of part (a), "N1,N2,..." (empty: 10^4, 10^5, 10^6)
    std::string scattered_field;  ///< scattered: --field given to `meshless isosurface` (empty: its default)
    double peer_timeout = 0;      ///< scattered: seconds per peer run (0: 120, --quick 30)
    bool no_peers = false;        ///< scattered: skip the Python/VTK peers
    std::string scale_sets;       ///< scale: "ct,clustered,layered" subset (empty: ct)
    std::string scale_ranks;      ///< scale: mpirun rank counts of the store runs, "2,4" (empty: none)
    std::string scattered_fields;         ///< scattered (a): "sphere,gyroid,ml" subset (empty: all three)
    std::string scattered_distributions;  ///< scattered (a): "uniform,clustered,layered" subset (empty: all)
    std::string scattered_parts;          ///< scattered: "a,b,c" subset (empty: all)
    bool all_peers = false;       ///< scattered: peers on every set (default: fewer on the large sizes)
    bool reuse_peers = false;     ///< scattered: take peer results kept in the work folder by earlier runs
    /// hierarchy-rmse: Hardy's c of the mpu fields, relative to each point set's bounding-box diagonal,
    /// one table per value, "C1,C2,..." (empty: the field's default, FieldParams::hardy_c_rel)
    std::string hardy_c;
    /// fields: FieldParams::hardy_c_spacing of every field built (negative: the field's default)
    double hardy_c_spacing = -1;
};

/// Free space in the scratch folder above which "bench all" includes the ooc section (its 4.4 GB
/// synthetic volume's store, the lung-sized sample store and the output point sets).
inline constexpr std::uint64_t kOocScratchRoom = 16ull << 30;

/// A table of strings: a header row and data rows, right-aligned numbers, left-aligned first column.
struct Table {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    void add(std::vector<std::string> row) { rows.push_back(std::move(row)); }
};

/// Prints sections, notes and tables to stdout as they are produced (flushed, so a long run shows
/// progress) and keeps the markdown rendering of everything for write_markdown().
class Report {
public:
    void title(const std::string& text);
    void section(const std::string& text);
    void note(const std::string& text);
    void table(const Table& t);
    /// Writes the markdown document (AtomicFile: temporary + rename).
    void write_markdown(const std::string& path) const;

private:
    std::string md_;
};

/// "AMD EPYC 7xx (2 logical cores)" from /proc/cpuinfo (or "unknown CPU").
std::string machine_description();
/// Local date and time "YYYY-MM-DD HH:MM".
std::string now_string();

/// Wall clock in milliseconds since construction.
class Stopwatch {
public:
    Stopwatch() : t0_(std::chrono::steady_clock::now()) {}
    double ms() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count();
    }

private:
    std::chrono::steady_clock::time_point t0_;
};

/// n uniform random points in the box [lo, hi] (SplitMix with this seed: the same points on every run).
std::vector<Vec3> random_box(const Vec3& lo, const Vec3& hi, std::size_t n, std::uint64_t seed);

/// Value + gradient evaluations of f on one thread (tbb::global_control) over the batch p, best of
/// reps (>= 1): per wall second, per CPU second of the calling thread (the same on an idle machine;
/// on a shared one the CPU rate is the field's own), and the fraction of values that are not finite.
struct EvalRate {
    double per_s = 0, per_cpu_s = 0, nan_share = 0;
};
EvalRate eval_rate_one_thread(const Field& f, const std::vector<Vec3>& p, int reps);

/// printf-style formatting into a std::string.
std::string fmt(const char* format, ...) __attribute__((format(printf, 1, 2)));
/// Bytes as "12.3 MiB" / "45.6 KiB".
std::string bytes_str(double bytes);
/// `s` single-quoted for /bin/sh (an embedded ' written as '\'').
std::string shell_quote(const std::string& s);
/// Runs a shell command, returns its stdout and exit status (-1 when it could not start).
std::pair<std::string, int> capture(const std::string& cmd);
/// The whole content of file `p` ("" when it cannot be read).
std::string read_file_bytes(const std::filesystem::path& p);

/// K isovalues spread over the data: evenly spaced quantiles (k+1)/(K+1) of the sample
/// histogram; integer sample types snap to "between grey levels" (floor + 0.5) so no sample
/// equals the isovalue. Duplicates are replaced by evenly spaced values over the range, so
/// fewer than K values come back only when the range has fewer than K distinct levels.
/// Sorted ascending; every value lies strictly inside (min, max) of the finite samples.
std::vector<double> pick_isovalues(const Volume& v, int k);

/// A benchmark volume: label, path relative to the data folder, and whether --quick skips it.
struct DataVolume {
    std::string label, rel_path;
    bool large = false;
};
/// The volumes of the speed benchmark (section 3.6), present or not.
std::vector<DataVolume> speed_volumes();

// The sections; each prints its tables into the report. Missing data is reported, not thrown.
/// Accuracy of the projected points against analytic surfaces (bench/bench_accuracy.cpp).
void run_accuracy(const BenchOptions& o, Report& r);
/// The volume rendering (bench/bench_render.cpp): LIDC2 512x512 trilinear ray casting on 1 and 2
/// threads, samples per second, skipping on/off; scattered samples of it through the mpu field, PSNR
/// against the volume's picture.
void run_render(const BenchOptions& o, Report& r);
/// Extraction time and memory, iso-splatting vs marching cubes vs VTK Flying Edges (bench/bench_speed.cpp).
void run_speed(const BenchOptions& o, Report& r);
/// Thread scaling of iso-splatting and identical output across thread counts (bench/bench_speed.cpp).
void run_threads(const BenchOptions& o, Report& r);
/// Splat rendering frame times, quad and EWA kernels, 36-frame turntable (bench/bench_splat.cpp).
void run_splat(const BenchOptions& o, Report& r);
/// The out-of-core numbers (bench/bench_ooc.cpp): conversion MB/s and ratio, store vs in-memory
/// throughput, paradigm (A) vs (C) vs marching cubes, threads and MPI ranks, peak RSS on >= 4 GiB.
/// Writes (and removes unless o.keep) a scratch folder under o.scratch_dir; takes minutes and GBs.
void run_ooc(const BenchOptions& o, Report& r);
/// The numbers for the meshless fields (bench/bench_fields.cpp): accuracy on Franke's 3-D function
/// and Marschner-Lobb vs SciPy's RBFInterpolator (bench/rbf_reference.py, run with o.python), linear
/// reproduction, Table 4.1 construction times on 1 and 2 threads, evaluation rate, 1M-point memory.
void run_fields(const BenchOptions& o, Report& r);
/// The whole-process numbers (bench/bench_process.cpp): the `meshless` binary (o.meshless) run as
/// users run it on the lung-sized CT, best-of-N wall clock and peak RSS (wait4), each row with the ratio
/// to its baseline measured in the same run: isosurface vs vtkFlyingEdges3D, pipes vs in-process,
/// 2 vs 1 threads, paradigm A vs C, splat throughput and RSS for 10^6..10^8 points. A command that
/// fails is an "n/a (reason)" row; the run goes on.
void run_process(const BenchOptions& o, Report& r);
/// The multiblock numbers (bench/bench_multiblock.cpp): `meshless split` + `isosurface BLOCKS` + `mc BLOCKS --stats`
/// on analytic fields in every multiblock layout and a 3-level AMR hierarchy, coverage of the true isosurface,
/// distance and normal errors next to the naive marching cubes' cracks; whole-process speed on the Table 4.1
/// sets and the combustor at 1 and 2 threads; VTK's per-block contour when python3-vtk9 is installed.
/// Commands that fail are "n/a (...)" cells; o.work_dir/multiblock (else a temp folder) holds the files.
void run_multiblock(const BenchOptions& o, Report& r);
/// The scattered-data numbers (bench/bench_scattered.cpp): `meshless isosurface POINTS` on analytic fields at scattered
/// points (uniform, clustered, layered; 10^4..10^6) against the truth and against SciPy griddata, vtkDelaunay3D and
/// vtkPointInterpolator (bench/scattered_peers.py) in the same run; Table 5.1 rebuilt from --stats; whole-process
/// time, peak RSS, thread and MPI-rank speed-ups on head samples of 10^5..10^6 points. Failing commands are
/// "n/a (...)" cells; o.work_dir/scattered (else a temp folder) holds the generated sets.
void run_scattered(const BenchOptions& o, Report& r);
/// "N1,N2,..." -> counts (each 10..1e8); throws std::invalid_argument naming --sizes otherwise.
std::vector<std::size_t> parse_scattered_sizes(const std::string& s);
/// scale: "2,4" as rank counts; throws std::invalid_argument naming --ranks.
std::vector<int> parse_rank_counts(const std::string& list);
/// scale: checks --sets and --ranks (std::invalid_argument naming the option).
void check_scale_options(const BenchOptions& o);
/// "a,b" -> {"a", "b"}.
std::vector<std::string> split_list(const std::string& s);
/// Checks --sizes, --fields, --distributions, --parts; throws std::invalid_argument naming the option.
void check_scattered_lists(const BenchOptions& o);

/// The cluster binary trees (bench/bench_hierarchy.cpp).
void run_hierarchy(const BenchOptions& o, Report& r);
/// The Python module's numbers (bench/bench_python.cpp, bench/python_module.py).
void run_python(const BenchOptions& o, Report& r);
/// bench/bench_scale.cpp: the scattered isosurface of LIDC2 samples at --sizes in memory, from a point
/// store in one slab and within two thirds of that memory, and the VTK peer (not part of `all`: hours at 10^7).
void run_scale(const BenchOptions& o, Report& r);
/// Its part (e) alone (`meshless-bench hierarchy-rmse`); `silicium` may be empty (read here).
void run_hierarchy_rmse(const BenchOptions& o, Report& r, const PointSet& silicium = {});

// ---- running processes (bench/process_run.cpp) ---------------------------------------------------

/// One process run: exit status, wall seconds, peak RSS (KiB) and its stderr.
struct Run {
    int code = -1;
    double seconds = 0;
    long maxrss_kib = 0;
    bool timed_out = false;  ///< killed (with its process group) at run_sh's time limit
    std::string err, out;
    bool ok() const { return code == 0 && !timed_out; }
    /// "exit 1: unknown option '--threads'" for n/a rows: the first line of stderr without the
    /// "meshless CMD: " prefix and the "(see ... --help)" hint, work-folder paths as WORK/, short.
    std::string why(const std::string& work = {}) const;
};

/// Runs `/bin/sh -c cmd` with stdin on /dev/null, stdout into out_file (or /dev/null), stderr into
/// err_file; wall time from before fork() to after wait4(); peak RSS of the shell and its children
/// alone (through run_rusage_wrapper: a process forked from this one would start with this
/// process's resident set as its high-water mark). limit_s > 0: the command runs in a process group
/// of its own, killed whole after limit_s seconds (Run::timed_out).
Run run_sh(const std::string& cmd, const std::filesystem::path& err_file, const std::filesystem::path& out_file = {},
           double limit_s = 0);

/// `meshless-bench --rusage-wrapper RSSFILE PROGRAM ARGS...` (used by run_process, not by users): runs
/// PROGRAM as a child, writes the child's ru_maxrss (KiB, its waited-for descendants included) to
/// RSSFILE and exits with the child's status. A fresh process, so the child's peak RSS is its own.
inline constexpr const char* kRusageWrapperFlag = "--rusage-wrapper";
int run_rusage_wrapper(int argc, char** argv);
/// True when o.scratch_dir (or the temp folder) has at least kOocScratchRoom bytes free.
bool ooc_scratch_has_room(const BenchOptions& o);

}  // namespace meshless::bench
