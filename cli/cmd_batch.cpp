// meshless batch: the nightly job's options, progress line, failure lines and exit status. The work
// is the recipe stream/batch_job.hpp, the table on stdout stream/batch_summary.hpp; exit status 2
// when some volume failed or was refused.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/progress_meter.hpp"
#include "stream/batch_job.hpp"
#include "stream/batch_ranks.hpp"
#include "stream/batch_summary.hpp"

namespace meshless::cli {

namespace {

/// Progress line on stderr (as every command's: when it is a terminal or MESHLESS_PROGRESS=always,
/// not with --quiet; first after progress_delay(), then at most 4 times a second):
///   "[2/5] chest: converting  37%; batch 23%, ETA 1:10"
class BatchProgressLine {
public:
    BatchProgressLine(bool on, double delay) : on_(on), delay_(delay) {}
    void show(const BatchProgress& p) {
        if (!on_) return;
        const double t = p.seconds;
        if (t < delay_ || (last_draw_ >= 0 && t - last_draw_ < 0.25 && p.fraction < 1 && p.what == last_what_)) return;
        last_draw_ = t;
        last_what_ = p.what;
        std::fprintf(stderr, "\r\033[K[%zu/%zu] %s: %s", p.index + 1, p.count, terminal_safe(p.name).c_str(), terminal_safe(p.what).c_str());
        if (p.fraction >= 0) std::fprintf(stderr, " %3.0f%%", 100 * p.fraction);
        if (p.batch > 0) std::fprintf(stderr, "; batch %.0f%%, ETA %s", 100 * p.batch, progress_clock_text(t * (1 - p.batch) / p.batch).c_str());
        std::fflush(stderr);
    }
    void clear() const {
        if (on_ && last_draw_ >= 0) std::fputs("\r\033[K", stderr);
    }

private:
    bool on_;
    double delay_;
    double last_draw_ = -1;
    std::string last_what_;
};

/// A manifest line's raw options, parsed as the command line's (InvalidArgument for a bad one).
RawOptions manifest_raw_options(const std::vector<std::string>& options) {
    std::vector<std::string> words{"meshless", "batch"};
    words.insert(words.end(), options.begin(), options.end());
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    Args a("batch", "", "");
    a.positionals(0, 0);
    add_volume_options(a);
    try {
        a.parse(static_cast<int>(argv.size()), argv.data(), 2);
        return raw_options(a);
    } catch (const UsageError& e) {
        throw InvalidArgument(e.what());
    }
}

/// The summary on stdout and the exit status of a run: 2 when a volume failed, 4 with --fail-empty when
/// an isovalue gave an empty point set or the archive holds no volume (warned on stderr), else 0.
int batch_result(const Args& a, const BatchRun& run) {
    print_batch_summary(stdout, run);
    if (run.archive_count == 0)
        std::fprintf(stderr, "meshless batch: warning: %s: no volumes (a folder's volume files, or a manifest's paths)\n",
                     terminal_safe(a.positional()[0]).c_str());
    if (run.any_failed()) return kExitData;
    return (run.any_empty() || run.archive_count == 0) && a.has("fail-empty") ? kExitEmpty : kExitOk;
}

/// batch --help: the nightly job.
constexpr const char* kBatchHelp =
           "The nightly job: converts every volume of an archive to a brick store OUT_DIR/NAME.mlb and\n"
           "iso-splats it into point sets OUT_DIR/NAME_iso<V>.ply (and NAME_iso<V>.mlp point streams with\n"
           "--formats ply,stream), one per --iso. ARCHIVE_DIR: every volume file in it (by extension, sorted\n"
           "by name; --recursive walks subfolders). MANIFEST: a text file, one volume path per line relative\n"
           "to the manifest's folder, '#' comments, optionally followed by raw options (--dims, --type, --endian,\n"
           "--spacing, --series, --array), e.g.\n"
           "    ct/chest.raw --dims 512,512,266 --type int16 --spacing 0.7,0.7,1.25\n"
           "Each output gets a sidecar OUT.meta recording the input's size, time and CRC-32, the parameters\n"
           "and the meshless version; outputs whose sidecar matches are skipped (up to date). Outputs and\n"
           "sidecars are written under temporary names and renamed, so a killed run, started again, finishes\n"
           "only what is left, with identical outputs. Bad inputs are reported and skipped; a summary table\n"
           "ends the run (stdout); progress is shown on stderr when it is a terminal.\n"
           "An input that is, or whose header names, a file outside its archive folder (ARCHIVE_DIR, or the\n"
           "manifest's folder; `..`, absolute paths and symbolic links resolved) is REFUSED: nothing of it is\n"
           "read or written, and the run goes on.\n"
           "A scheduler's job array splits an archive with --shard K/N: each job converts its share (every\n"
           "volume in exactly one shard, the largest first), the outputs and sidecars those of one run.\n"
           "Under mpirun -np N, rank 0 deals the volumes to the ranks on request, largest first (a rank asks\n"
           "for its next when it has finished one), and prints the one summary of the whole archive (and\n"
           "gives the exit status); the outputs are those of one process.";

/// The run's settings from the options (UsageError for a bad value).
BatchSettings batch_settings(const Args& a, const ConvertParams& defaults) {
    BatchSettings s;
    s.out_dir = a.require("output");
    for (const auto& v : a.get_all("iso")) {
        const double iso = parse_double(v, "--iso");
        if (!std::isfinite(iso)) throw UsageError("--iso: must be a finite number, got '" + v + "'");
        const std::string name = batch_iso_name(iso);
        if (std::any_of(s.isos.begin(), s.isos.end(), [&](double other) { return batch_iso_name(other) == name; }))
            throw UsageError("--iso " + v + " given twice (outputs are named by the isovalue: _iso" + name + ")");
        s.isos.push_back(iso);
    }
    s.ply = false;
    for (std::string list = a.get_or("formats", "ply"), f; !list.empty();) {
        const auto comma = list.find(',');
        f = list.substr(0, comma);
        list = comma == std::string::npos ? "" : list.substr(comma + 1);
        if (f == "ply") s.ply = true;
        else if (f == "stream" || f == "mlp") s.stream = true;
        else if (f != "none") throw UsageError("--formats: expected ply, stream or none, got '" + f + "'");
    }
    if (a.has("stream")) s.stream = true;
    s.rehash = a.has("rehash");
    s.recursive = a.has("recursive");
    const long long brick = a.get_int_or("brick", defaults.brick_edge);
    if (brick < 2 || brick > 1024) throw UsageError("--brick: expected 2..1024 cells");
    s.convert.brick_edge = static_cast<std::uint32_t>(brick);
    const long long level = a.get_int_or("zstd-level", defaults.zstd_level);
    if (level < -7 || level > 22) throw UsageError("--zstd-level: expected a zstd level, -7..22");
    s.convert.zstd_level = static_cast<int>(level);
    s.mode = parse_projection(a.get_or("projection", "approx"));
    s.sampling = sampling_params(a);
    s.memory = parse_memory_size(a.get_or("memory", "256M"));
    s.threads = threads(a);
    s.convert.threads = s.threads;
    if (const auto shard = a.get("shard")) {
        const auto slash = shard->find('/');
        const long long k = slash == std::string::npos ? 0 : parse_int(shard->substr(0, slash), "--shard");
        const long long n = slash == std::string::npos ? 0 : parse_int(shard->substr(slash + 1), "--shard");
        if (n < 1 || n > 100000 || k < 1 || k > n)
            throw UsageError("--shard: expected K/N with 1 <= K <= N <= 100000, got '" + *shard + "'");
        s.shard = static_cast<std::uint32_t>(k - 1);
        s.shards = static_cast<std::uint32_t>(n);
    }
    return s;
}

}  // namespace

int cmd_batch(int argc, char** argv) {
    const ConvertParams defaults;
    Args a("batch", "ARCHIVE_DIR|MANIFEST -o OUT_DIR --iso V [--iso V2 ...] [options]",
           kBatchHelp);
    a.positionals(0, 1);
    a.option("output", "o", "DIR", "output folder (created when missing; required)")
        .option("iso", "", "V", "isovalue; repeat for several (none: brick stores only)").repeatable()
        .option("formats", "", "LIST", "point set outputs: ply, stream, ply,stream or none", "ply")
        .flag("stream", "also write point streams (same as adding 'stream' to --formats)")
        .option("brick", "", "B", "brick edge in cells, 2..1024", std::to_string(defaults.brick_edge))
        .option("zstd-level", "", "L", "zstd level of the bricks, -7..22", std::to_string(defaults.zstd_level))
        .deprecated_alias("level")
        .option("projection", "", "MODE", "approx | exact | none", "approx")
        .flag("recursive", "ARCHIVE_DIR: also walk subfolders (outputs mirror them)")
        .flag("rehash", "hash every input, even when its size and time are those recorded")
        .option("shard", "", "K/N", "convert only shard K of N (K = 1..N, a job array's task): the volumes by size, largest first, "
                "dealt round-robin; shards run side by side into one OUT_DIR");
    add_fail_empty_option(a);
    add_sampling_options(a);
    add_memory_option(a);
    add_thread_option(a);
    add_quiet_option(a);
    a.epilog("examples: meshless batch ../shared/data/fuel -o out --iso 20.5 --iso 100.5\n"
             "          meshless batch archive.txt -o /data/points --iso 500 --formats ply,stream --memory 1G\n"
             "exit status: 0 everything done or up to date, 2 some volume failed or was refused (see the table), 1 usage error,\n"
             "             4 (with --fail-empty, none failed) some isovalue gave an empty point set, or the archive holds no volume.\n");
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().empty()) throw UsageError("missing ARCHIVE_DIR or MANIFEST (see meshless batch --help)");

    const BatchSettings s = batch_settings(a, defaults);
    BatchProgressLine line(progress_wanted(a), progress_delay());
    BatchCallbacks cb;
    cb.parse_raw = manifest_raw_options;
    cb.progress = [&](const BatchProgress& p) { line.show(p); };
    cb.iso_range = [](double iso, const std::array<double, 2>& range, const std::string& source) { warn_if_iso_outside(iso, range, source); };
    cb.item_done = [&](const BatchItemResult& r) {
        line.clear();
        print_batch_item_failure(stderr, r);
    };
    if (launched_world_size() > 1) {  // the ranks share the archive; rank 0 prints the one summary
        MpiSession mpi(&argc, &argv);
        try {
            if (mpi.rank() != 0) cb.progress = nullptr;
            const BatchRun run = run_batch_ranks(a.positional()[0], s, cb, mpi, [&mpi](std::exception_ptr e) { end_mpi_job(mpi, "batch", e); });
            if (mpi.rank() != 0) return kExitOk;
            line.clear();
            return batch_result(a, run);
        } catch (const std::exception& e) {
            return end_mpi_run(mpi, "batch", e);
        }
    }
    return batch_result(a, run_batch(a.positional()[0], s, cb));
}

}  // namespace meshless::cli
