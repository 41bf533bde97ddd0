// meshless batch: the nightly job. Converts every volume of an archive (a directory or a manifest)
// to a brick store and iso-splatted point sets (PLY and/or point stream), skipping outputs whose
// sidecar says they are up to date (cli/batch_sidecar.hpp), going on past bad inputs, and ending
// with a summary table (stdout) and exit status 2 when anything failed.
// Crash safety: every output and sidecar is written to a temporary name and renamed, the sidecar
// after its output, and a stale sidecar is removed before its output is redone; so a run killed at
// any point leaves complete outputs (with or without sidecar) and temporaries, which the next run
// removes before finishing only what is left. Outputs are deterministic, so the result is
// byte-identical to a clean run. A lock file in OUT_DIR keeps two runs from sharing it.
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "cli/batch_inputs.hpp"
#include "cli/batch_sidecar.hpp"
#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/progress_meter.hpp"
#include "formats/atomic_file.hpp"
#include "formats/point_stream.hpp"
#include "formats/reference_policy.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_converter.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/brick_store.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless::cli {

namespace {

/// Bumped when a reader places or orients data differently, so that `batch` rebuilds what an
/// earlier revision made (1: the first readers; 2: backward direction matrices in world coordinates;
/// 3: stores record the patient axes, points their patient_axes and value range).
constexpr int kReadersRevision = 3;


namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Hands every batch to one or two sinks (the PLY and the point stream of one isovalue).
class TeeSink final : public Sink {
public:
    TeeSink(Sink* a, Sink* b) : a_(a), b_(b) {}
    void consume(Batch&& batch) override {
        if (a_ && b_) {
            Batch copy = batch;
            a_->consume(std::move(copy));
            b_->consume(std::move(batch));
        } else {
            (a_ ? a_ : b_)->consume(std::move(batch));
        }
    }
    void finish() override {
        if (a_) a_->finish();
        if (b_) b_->finish();
    }

private:
    Sink* a_;
    Sink* b_;
};

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

struct Settings {
    std::string out_dir;
    std::vector<double> isos;
    std::vector<std::string> iso_names;  ///< "%.9g" of each isovalue, used in file names
    bool ply = true, stream = false, rehash = false;
    ConvertParams convert;
    Projection mode = Projection::approx;
    SamplingParams sampling;
    std::uint64_t memory = 0;
    int threads = 1;
    bool progress = false;  ///< the progress line (progress_wanted)
};

enum class Status { done, up_to_date, failed, refused };

struct ItemResult {
    std::string name;
    Status status = Status::failed;
    int written = 0, current = 0;
    double seconds = 0;
    std::string message;
};

/// True for I/O errors that mean the disk is full: no point going on with the other volumes.
bool is_disk_full(const std::string& msg) {
    for (int e : {ENOSPC, EDQUOT})
        if (msg.find(std::strerror(e)) != std::string::npos) return true;
    return false;
}
/// True when a file hit the size limit (ulimit -f, or the file system's largest file): this volume
/// fails, smaller ones may still fit.
bool is_file_too_large(const std::string& msg) { return msg.find(std::strerror(EFBIG)) != std::string::npos; }

void remove_quietly(const std::string& p) {
    std::error_code ec;
    fs::remove(p, ec);
}

/// Removes "<output>.tmp-<pid>[.spool]" (and the same for sidecars) left by killed runs: only for
/// the outputs this run plans, only when process <pid> is gone.
int remove_stale_temporaries(const std::set<std::string>& planned) {
    std::set<fs::path> dirs;
    for (const auto& p : planned) dirs.insert(fs::path(p).parent_path());
    int removed = 0;
    for (const auto& d : dirs) {
        std::error_code ec;
        for (fs::directory_iterator it(d, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string full = it->path().string();
            const auto t = full.rfind(".tmp-");
            if (t == std::string::npos || !planned.count(full.substr(0, t))) continue;
            std::string rest = full.substr(t + 5);
            if (rest.size() > 6 && rest.compare(rest.size() - 6, 6, ".spool") == 0) rest.resize(rest.size() - 6);
            if (rest.empty() || rest.size() > 9 || !std::all_of(rest.begin(), rest.end(), [](char c) { return c >= '0' && c <= '9'; }))
                continue;
            const pid_t pid = static_cast<pid_t>(std::stol(rest));
            if (pid == ::getpid() || (::kill(pid, 0) == 0 || errno != ESRCH)) continue;
            if (fs::remove(it->path(), ec)) ++removed;
        }
    }
    return removed;
}

/// Holds an exclusive flock on OUT_DIR/.meshless-batch.lock for the run (released on exit or kill).
class DirLock {
public:
    explicit DirLock(const std::string& dir) {
        const std::string p = (fs::path(dir) / ".meshless-batch.lock").string();
        fd_ = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd_ < 0) throw IoError(p + ": cannot create lock file (" + std::strerror(errno) + ")");
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            ::close(fd_);
            throw IoError(dir + ": another meshless batch is writing to this folder (" + p + " is locked)");
        }
    }
    ~DirLock() { ::close(fd_); }
    DirLock(const DirLock&) = delete;
    DirLock& operator=(const DirLock&) = delete;

private:
    int fd_ = -1;
};

/// Progress line on stderr (as every command's: when it is a terminal or MESHLESS_PROGRESS=always,
/// not with --quiet; first after progress_delay(), then at most 4 times a second):
///   "[2/5] chest: converting  37%; batch 23%, ETA 1:10"
/// The batch's fraction weighs each volume by its input size (a volume's conversion dominates its
/// time): the finished volumes plus the running one's conversion fraction.
struct Progress {
    using Clock = std::chrono::steady_clock;
    bool on = false;
    double delay = 1.0;
    std::size_t index = 0, count = 0;
    std::string name;
    std::vector<double> weight;  ///< per volume: its input bytes (at least 1)
    double total = 0, finished = 0;
    Clock::time_point start = Clock::now();
    mutable double last_draw = -1;
    mutable double item_fraction = 0;  ///< the running volume's last fraction (its later steps keep it)
    mutable std::string last_what;

    void finish_item() {
        if (index < weight.size()) finished += weight[index];
        item_fraction = 0;
    }
    void show(const std::string& what, double fraction = -1) const {
        if (!on) return;
        const double t = std::chrono::duration<double>(Clock::now() - start).count();
        if (fraction >= 0) item_fraction = std::clamp(fraction, 0.0, 1.0);
        if (t < delay || (last_draw >= 0 && t - last_draw < 0.25 && fraction < 1 && what == last_what)) return;
        last_draw = t;
        last_what = what;
        std::fprintf(stderr, "\r\033[K[%zu/%zu] %s: %s", index + 1, count, terminal_safe(name).c_str(), terminal_safe(what).c_str());
        if (fraction >= 0) std::fprintf(stderr, " %3.0f%%", 100 * fraction);
        const double cur = index < weight.size() ? weight[index] * item_fraction : 0;
        const double f = total > 0 ? std::clamp((finished + cur) / total, 0.0, 1.0) : 0;
        if (f > 0) std::fprintf(stderr, "; batch %.0f%%, ETA %s", 100 * f, progress_clock_text(t * (1 - f) / f).c_str());
        std::fflush(stderr);
    }
    void clear() const {
        if (on && last_draw >= 0) std::fputs("\r\033[K", stderr);
    }
};

class ItemRunner {
public:
    ItemRunner(const Settings& s, const BatchItem& item, const Progress& progress)
        : s_(s), item_(item), progress_(progress), base_((fs::path(s.out_dir) / item.name).string()) {}

    /// Output paths of this item (for the stale-temporary sweep).
    static std::vector<std::string> outputs(const Settings& s, const std::string& name) {
        const std::string base = (fs::path(s.out_dir) / name).string();
        std::vector<std::string> out{base + ".mlb"};
        for (const auto& n : s.iso_names) {
            if (s.ply) out.push_back(base + "_iso" + n + ".ply");
            if (s.stream) out.push_back(base + "_iso" + n + ".mlp");
        }
        return out;
    }

    void run(ItemResult& r) {
        if (!item_.error.empty()) throw UsageError(item_.error);
        std::error_code ec;
        if (!fs::exists(item_.path, ec)) throw IoError(item_.path + ": missing input (no such file or directory)");
        const VolumeInfo info = probe_volume(item_.path, item_.raw);
        std::vector<std::string> files{item_.path};
        if (fs::is_directory(item_.path, ec) && fs::is_regular_file(fs::path(item_.path) / "index.json", ec))
            files.push_back((fs::path(item_.path) / "index.json").string());  // vtk-js: the index is part of it
        for (const auto& f : info.data_files)
            if (std::find(files.begin(), files.end(), f) == files.end() && !fs::equivalent(f, item_.path, ec)) files.push_back(f);
        stats_ = stat_files(files);
        fs::create_directories(fs::path(base_).parent_path(), ec);

        // the brick store
        const std::string mlb = base_ + ".mlb";
        Sidecar mlb_side = common();
        mlb_side["kind"] = "brick-store";
        mlb_side["param.brick"] = std::to_string(s_.convert.brick_edge);
        mlb_side["param.level"] = std::to_string(s_.convert.zstd_level);
        if (up_to_date(mlb, mlb_side)) {
            ++r.current;
        } else {
            remove_quietly(sidecar_path(mlb));
            const std::uint32_t c = crc();  // hash before converting: a change meanwhile shows in the stats
            progress_.show("converting", 0);
            auto src = open_slice_source(item_.path, item_.raw);
            ConvertParams cp = s_.convert;  // the store keeps the volume's patient axes, as convert's does
            if (info.frame) cp.patient_axes = frame_axes(*info.frame);
            convert_to_brick_store(*src, mlb, cp, [&](double f) { progress_.show("converting", f); });
            check_unchanged({mlb});
            record(mlb, mlb_side, c);
            ++r.written;
        }

        // the point sets, one pass per isovalue feeding the PLY and/or the stream
        std::unique_ptr<BrickStore> store;
        std::unique_ptr<BrickCache> cache;
        std::unique_ptr<BrickIndex> index;
        for (std::size_t k = 0; k < s_.isos.size(); ++k) {
            const double iso = s_.isos[k];
            Sidecar side = common();
            side["param.brick"] = std::to_string(s_.convert.brick_edge);
            side["param.iso"] = fmt("%.17g", iso);
            side["param.projection"] = to_string(s_.mode);
            side["param.radius_scale"] = fmt("%.17g", s_.sampling.radius_scale);
            const std::string ply = base_ + "_iso" + s_.iso_names[k] + ".ply", mlp = base_ + "_iso" + s_.iso_names[k] + ".mlp";
            Sidecar ply_side = side, mlp_side = side;
            ply_side["kind"] = "ply-points";
            mlp_side["kind"] = "point-stream";
            const bool do_ply = s_.ply && !up_to_date(ply, ply_side);
            const bool do_mlp = s_.stream && !up_to_date(mlp, mlp_side);
            r.current += (s_.ply && !do_ply) + (s_.stream && !do_mlp);
            if (!do_ply && !do_mlp) continue;
            const std::uint32_t c = crc();
            if (!store) {
                store = BrickStore::open(mlb);
                cache = std::make_unique<BrickCache>(*store, s_.memory);
                index = std::make_unique<BrickIndex>(*store);
            }
            progress_.show("iso " + s_.iso_names[k]);
            const auto& si = store->info();
            warn_if_iso_outside(iso, {si.value_min, si.value_max}, item_.path);
            StreamMeta meta = volume_meta(mlb, si.grid, si.type, {si.value_min, si.value_max}, iso,
                                          "meshless isosurface " + fs::path(mlb).filename().string() + " --iso " +
                                              s_.iso_names[k] + " --projection " + to_string(s_.mode));
            meta.set("projection", to_string(s_.mode));
            set_surface_bounds(meta, store_surface_bounds(*store, *index, iso));  // frame as isosurface does
            set_patient_axes(meta, store_frame(si));
            if (do_ply) remove_quietly(sidecar_path(ply));
            if (do_mlp) remove_quietly(sidecar_path(mlp));
            // on failure, whichever of these is in place without a sidecar is removed (no output that
            // looks complete without being recorded; the old version's sidecar is already gone)
            std::vector<std::string> unrecorded;
            if (do_ply) unrecorded.push_back(ply);
            if (do_mlp) unrecorded.push_back(mlp);
            try {
                std::optional<PlySink> ply_sink;
                std::unique_ptr<AtomicFile> mlp_file;
                std::optional<StreamSink> mlp_sink;
                if (do_ply) ply_sink.emplace(ply, ply_comments(meta));
                if (do_mlp) {
                    mlp_file = std::make_unique<AtomicFile>(mlp);
                    mlp_sink.emplace(mlp_file->handle(), mlp, RecordKind::point, meta);
                }
                TeeSink tee(ply_sink ? &*ply_sink : nullptr, mlp_sink ? &*mlp_sink : nullptr);
                run_isosplat_bricks(*store, *cache, index->active(iso), iso, s_.mode, s_.sampling, tee, {s_.threads});
                if (mlp_file) mlp_file->commit();
                check_unchanged(unrecorded);
                if (do_ply) record(ply, ply_side, c);
                if (do_mlp) record(mlp, mlp_side, c);
            } catch (...) {
                for (const auto& p : unrecorded)
                    if (!fs::exists(sidecar_path(p), ec)) remove_quietly(p);
                throw;
            }
            r.written += do_ply + do_mlp;
        }
    }

private:
    Sidecar common() const {
        Sidecar s;
        // readers revision (kReadersRevision): outputs made by an earlier revision are out of date
        s["meshless"] = std::string(kMeshlessVersion) + " (brick store v" + std::to_string(kBrickStoreVersion) +
                        ", point stream v" + std::to_string(kStreamVersion) + ", readers r" + std::to_string(kReadersRevision) + ")";
        s["param.raw"] = item_.raw_text;
        return s;
    }

    /// The input's CRC-32: from a sidecar whose stat list equals the current one (unless --rehash),
    /// else computed over the input's bytes (once per item).
    std::uint32_t crc() {
        if (crc_) return *crc_;
        progress_.show("hashing input");
        crc_ = crc32_files(stats_);
        return *crc_;
    }
    std::optional<std::uint32_t> crc_from(const Sidecar& sc) {
        if (!crc_ && !s_.rehash && recorded_files(sc) == stats_) crc_ = recorded_crc(sc);
        return crc_;
    }

    /// Output present, its size as recorded, and the sidecar's identity as expected. A touched
    /// input with the same bytes stays up to date (its sidecar is refreshed with the new stats).
    bool up_to_date(const std::string& out, const Sidecar& expected) {
        const auto sc = read_sidecar(sidecar_path(out));
        if (!sc) return false;
        std::error_code ec;
        const auto size = fs::file_size(out, ec);
        const auto rec = sc->find("output_size");
        if (ec || rec == sc->end() || rec->second != std::to_string(size)) return false;
        crc_from(*sc);
        Sidecar full = expected;
        put_input(full, item_.path, stats_, crc());
        if (!same_identity(*sc, full)) return false;
        if (recorded_files(*sc) != stats_ || sc->find("input") == sc->end() || sc->at("input") != item_.path) {
            full["output"] = fs::path(out).filename().string();
            full["output_size"] = rec->second;
            write_sidecar(sidecar_path(out), full);
        }
        return true;
    }

    void record(const std::string& out, Sidecar side, std::uint32_t crc) {
        sync_to_disk(out);  // the output on disk before the sidecar that says it is complete
        put_input(side, item_.path, stats_, crc);
        side["output"] = fs::path(out).filename().string();
        side["output_size"] = std::to_string(fs::file_size(out));
        write_sidecar(sidecar_path(out), side);
    }

    /// The input must not change while its outputs are made; if it did, they are removed.
    void check_unchanged(const std::vector<std::string>& made) {
        std::vector<std::string> paths;
        for (const auto& f : stats_) paths.push_back(f.path);
        if (stat_files(paths) == stats_) return;
        for (const auto& p : made) remove_quietly(p);
        throw IoError(item_.path + ": changed while being processed; run again");
    }

    const Settings& s_;
    const BatchItem& item_;
    const Progress& progress_;
    std::string base_;
    std::vector<FileStat> stats_;
    std::optional<std::uint32_t> crc_;
};

const char* status_text(Status s) {
    switch (s) {
        case Status::done: return "done";
        case Status::up_to_date: return "up to date";
        case Status::failed: return "FAILED";
        case Status::refused: return "REFUSED";
    }
    return "?";
}

void print_summary(const std::vector<ItemResult>& results, double seconds) {
    std::size_t w = 6;
    for (const auto& r : results) w = std::max(w, terminal_safe(r.name).size());
    std::printf("%-*s  %-10s  %7s  %10s  %8s\n", static_cast<int>(w), "volume", "result", "written", "up to date", "seconds");
    int done = 0, current = 0, failed = 0, refused = 0, written = 0, outputs_current = 0;
    for (const auto& r : results) {
        std::printf("%-*s  %-10s  %7d  %10d  %8.2f%s%s\n", static_cast<int>(w), terminal_safe(r.name).c_str(), status_text(r.status), r.written,
                    r.current, r.seconds, r.message.empty() ? "" : "  ", terminal_safe(r.message).c_str());
        done += r.status == Status::done;
        current += r.status == Status::up_to_date;
        failed += r.status == Status::failed;
        refused += r.status == Status::refused;
        written += r.written;
        outputs_current += r.current;
    }
    const std::string refused_text = refused ? ", " + std::to_string(refused) + " refused" : "";
    std::printf("%zu volume(s): %d done, %d up to date, %d failed%s; %d output(s) written, %d up to date; %.2f s\n",
                results.size(), done, current, failed, refused_text.c_str(), written, outputs_current, seconds);
    std::fflush(stdout);
}

/// batch --help: the nightly job.
constexpr const char* kBatchHelp =
           "The nightly job: converts every volume of an archive to a brick store OUT_DIR/NAME.mlb and\n"
           "iso-splats it into point sets OUT_DIR/NAME_iso<V>.ply (and NAME_iso<V>.mlp point streams with\n"
           "--formats ply,stream), one per --iso. ARCHIVE_DIR: every volume file in it (by extension, sorted\n"
           "by name; --recursive walks subfolders). MANIFEST: a text file, one volume path per line relative\n"
           "to the manifest's folder, '#' comments, optionally followed by raw options, e.g.\n"
           "    ct/chest.raw --dims 512,512,266 --type int16 --spacing 0.7,0.7,1.25\n"
           "Each output gets a sidecar OUT.meta recording the input's size, time and CRC-32, the parameters\n"
           "and the meshless version; outputs whose sidecar matches are skipped (up to date). Outputs and\n"
           "sidecars are written under temporary names and renamed, so a killed run, started again, finishes\n"
           "only what is left, with identical outputs. Bad inputs are reported and skipped; a summary table\n"
           "ends the run (stdout); progress is shown on stderr when it is a terminal.\n"
           "An input that is, or whose header names, a file outside its archive folder (ARCHIVE_DIR, or the\n"
           "manifest's folder; `..`, absolute paths and symbolic links resolved) is REFUSED: nothing of it is\n"
           "read or written, and the run goes on.";

/// The run's settings from the options (UsageError for a bad value).
Settings batch_settings(const Args& a, const ConvertParams& defaults) {
    Settings s;
    s.out_dir = a.require("output");
    for (const auto& v : a.get_all("iso")) {
        const double iso = parse_double(v, "--iso");
        if (!std::isfinite(iso)) throw UsageError("--iso: must be a finite number, got '" + v + "'");
        const std::string name = fmt("%.9g", iso);
        if (std::find(s.iso_names.begin(), s.iso_names.end(), name) != s.iso_names.end())
            throw UsageError("--iso " + v + " given twice (outputs are named by the isovalue: _iso" + name + ")");
        s.isos.push_back(iso);
        s.iso_names.push_back(name);
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
    s.progress = progress_wanted(a);

    return s;
}

/// A failed item on stderr; a full disk stops the run (disk_full says why, the rest is not attempted).
void report_failure(ItemResult& r, const Settings& s, std::string& disk_full) {
    if (is_file_too_large(r.message))
        r.message += "; over the file size limit (ulimit -f, or the file system's largest file); "
                     "temporaries removed";
    std::fprintf(stderr, "meshless batch: %s: %s\n", terminal_safe(r.name).c_str(), terminal_safe(r.message).c_str());
    if (is_disk_full(r.message)) {
        disk_full = "out of disk space in " + s.out_dir;
        std::fprintf(stderr,
                     "meshless batch: %s; stopping. Finished outputs are kept, temporaries removed; free some space "
                     "and run the same command again to finish the rest\n",
                     terminal_safe(disk_full).c_str());
    }
}

/// Every output (and sidecar) the items will write; an item whose outputs another item already
/// claims gets an error instead (reported, nothing written for it).
std::set<std::string> plan_outputs(const Settings& s, std::vector<BatchItem>& items) {
    std::set<std::string> planned;
    std::map<std::string, std::string> owner;  // output name -> input that claimed it
    for (auto& it : items) {
        if (!it.error.empty()) continue;
        if (auto [pos, fresh] = owner.emplace(it.name, it.path); !fresh) {
            it.error = it.path + ": its outputs would be named '" + it.name + "', like those of " + pos->second;
            continue;
        }
        for (const auto& o : ItemRunner::outputs(s, it.name)) {
            planned.insert(o);
            planned.insert(sidecar_path(o));
        }
    }
    return planned;
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
        .option("brick", "", "B", "brick edge in cells", std::to_string(defaults.brick_edge))
        .option("zstd-level", "", "L", "zstd level of the bricks", std::to_string(defaults.zstd_level))
        .deprecated_alias("level")
        .option("projection", "", "MODE", "approx | exact | none", "approx")
        .flag("recursive", "ARCHIVE_DIR: also walk subfolders (outputs mirror them)")
        .flag("rehash", "hash every input, even when its size and time are those recorded");
    add_sampling_options(a);
    add_memory_option(a);
    add_thread_option(a);
    add_quiet_option(a);
    a.epilog("examples: meshless batch ../shared/data/fuel -o out --iso 20.5 --iso 100.5\n"
             "          meshless batch archive.txt -o /data/points --iso 500 --formats ply,stream --memory 1G\n"
             "exit status: 0 everything done or up to date, 2 some volume failed or was refused (see the table), 1 usage error.\n");
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().empty()) throw UsageError("missing ARCHIVE_DIR or MANIFEST (see meshless batch --help)");
    const std::string input = a.positional()[0];

    const Settings s = batch_settings(a, defaults);
    std::error_code ec;
    const bool is_dir = fs::is_directory(input, ec);
    if (!is_dir && !fs::exists(input, ec)) throw IoError(input + ": no such archive folder or manifest");
    if (!is_dir && looks_like_volume(input))
        throw UsageError(input + " is a volume; give a folder of volumes or a manifest (one path per line)");
    make_output_folder(s.out_dir);
    DirLock lock(s.out_dir);

    std::vector<BatchItem> items = is_dir ? list_archive_dir(input, a.has("recursive"), s.out_dir) : read_manifest(input);
    const std::set<std::string> planned = plan_outputs(s, items);
    remove_stale_temporaries(planned);

    const auto t0 = Clock::now();
    std::vector<ItemResult> results;
    std::string disk_full;
    Progress progress;
    progress.on = s.progress;
    progress.delay = progress_delay();
    progress.count = items.size();
    for (const BatchItem& it : items) {
        std::error_code size_ec;
        const auto bytes = fs::file_size(it.path, size_ec);
        progress.weight.push_back(size_ec ? 1.0 : std::max(1.0, static_cast<double>(bytes)));
        progress.total += progress.weight.back();
    }
    for (std::size_t i = 0; i < items.size(); ++i) {
        ItemResult r;
        r.name = items[i].name;
        if (!disk_full.empty()) {
            r.message = "not attempted: " + disk_full;
            results.push_back(std::move(r));
            continue;
        }
        progress.index = i;
        progress.name = items[i].name;
        const auto t = Clock::now();
        try {
            ItemRunner(s, items[i], progress).run(r);
            r.status = r.written > 0 ? Status::done : Status::up_to_date;
        } catch (const BrokenPipe&) {
            throw;
        } catch (const ReferenceRefused& e) {  // a reference out of the archive: nothing read or written for it
            r.status = Status::refused;
            r.message = e.what();
        } catch (const std::bad_alloc&) {
            r.message = "out of memory";
        } catch (const std::exception& e) {
            r.message = e.what();
        }
        r.seconds = std::chrono::duration<double>(Clock::now() - t).count();
        progress.clear();
        progress.finish_item();
        if (r.status == Status::refused)
            std::fprintf(stderr, "meshless batch: %s: %s\n", terminal_safe(r.name).c_str(), terminal_safe(r.message).c_str());
        if (r.status == Status::failed) report_failure(r, s, disk_full);
        results.push_back(std::move(r));
    }
    print_summary(results, std::chrono::duration<double>(Clock::now() - t0).count());
    return std::any_of(results.begin(), results.end(),
                       [](const ItemResult& r) { return r.status == Status::failed || r.status == Status::refused; })
               ? 2
               : 0;
}

}  // namespace meshless::cli
