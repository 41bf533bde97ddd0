#include "stream/batch_job.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include "formats/anatomical_frame.hpp"
#include "formats/atomic_file.hpp"
#include "formats/output_folder.hpp"
#include "formats/point_stream.hpp"
#include "formats/reference_policy.hpp"
#include "formats/temporary_files.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/slice_source.hpp"
#include "stream/batch_lock.hpp"
#include "stream/batch_shard.hpp"
#include "stream/batch_sidecar.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"
#include "stream/stream_endpoints.hpp"
#include "stream/stream_metadata.hpp"
#include "stream/tee_sink.hpp"

namespace meshless {

namespace {

/// Bumped when a reader places or orients data differently, so that `batch` rebuilds what an
/// earlier revision made (1: the first readers; 2: backward direction matrices in world coordinates;
/// 3: stores record the patient axes, points their patient_axes and value range; 4: stores and
/// points record the length unit, pictures draw the axes where it is known).
constexpr int kReadersRevision = 4;

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

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

/// The steps of the running volume as BatchProgress: the batch's fraction weighs each volume by its
/// input size (a volume's conversion dominates its time), the finished volumes plus the running
/// one's conversion fraction.
class ProgressReport {
public:
    /// dealt_share (a dynamic deal): the batch fraction is the share of the archive dealt to any rank.
    ProgressReport(const std::function<void(const BatchProgress&)>& report, const std::vector<BatchItem>& items,
                   std::function<double()> dealt_share = {})
        : report_(report), dealt_share_(std::move(dealt_share)) {
        p_.count = items.size();
        for (const BatchItem& it : items) {
            std::error_code ec;
            const auto bytes = fs::file_size(it.path, ec);
            weight_.push_back(ec ? 1.0 : std::max(1.0, static_cast<double>(bytes)));
            total_ += weight_.back();
        }
    }
    void start_item(std::size_t index, const std::string& name) {
        p_.index = index;
        p_.name = name;
    }
    void finish_item() {
        if (p_.index < weight_.size()) finished_ += weight_[p_.index];
        item_fraction_ = 0;
    }
    void show(const std::string& what, double fraction = -1) {
        if (!report_) return;
        if (fraction >= 0) item_fraction_ = std::clamp(fraction, 0.0, 1.0);  // its later steps keep it
        const double cur = p_.index < weight_.size() ? weight_[p_.index] * item_fraction_ : 0;
        p_.what = what;
        p_.fraction = fraction;
        p_.batch = dealt_share_ ? std::clamp(dealt_share_(), 0.0, 1.0)
                                : total_ > 0 ? std::clamp((finished_ + cur) / total_, 0.0, 1.0) : 0;
        p_.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
        report_(p_);
    }

private:
    const std::function<void(const BatchProgress&)>& report_;
    std::function<double()> dealt_share_;
    BatchProgress p_;
    std::vector<double> weight_;  ///< per volume: its input bytes (at least 1)
    double total_ = 0, finished_ = 0;
    double item_fraction_ = 0;  ///< the running volume's last fraction
    Clock::time_point start_ = Clock::now();
};

/// Output paths of the volume named `name` (without sidecars).
std::vector<std::string> item_outputs(const BatchSettings& s, const std::string& name) {
    const std::string base = (fs::path(s.out_dir) / name).string();
    std::vector<std::string> out{base + ".mlb"};
    for (double iso : s.isos) {
        const std::string n = batch_iso_name(iso);
        if (s.ply) out.push_back(base + "_iso" + n + ".ply");
        if (s.stream) out.push_back(base + "_iso" + n + ".mlp");
    }
    return out;
}

/// Makes one volume's outputs up to date, counting in the result as it goes.
class ItemRunner {
public:
    ItemRunner(const BatchSettings& s, const BatchItem& item, const BatchCallbacks& cb, ProgressReport& progress)
        : s_(s), item_(item), cb_(cb), progress_(progress), base_((fs::path(s.out_dir) / item.name).string()) {}

    void run(BatchItemResult& r) {
        if (!item_.error.empty()) throw InvalidArgument(item_.error);
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
            cp.length_unit = info.length_unit;
            cp.value_unit = info.value_unit;
            convert_to_brick_store(*src, mlb, cp, [&](double f) { progress_.show("converting", f); });
            check_unchanged({mlb});
            record(mlb, mlb_side, c);
            ++r.written;
        }

        // the point sets, one pass per isovalue feeding the PLY and/or the stream
        std::unique_ptr<BrickStore> store;
        std::unique_ptr<BrickCache> cache;
        std::unique_ptr<BrickIndex> index;
        for (const double iso : s_.isos) {
            const std::string iso_name = batch_iso_name(iso);
            Sidecar side = common();
            side["param.brick"] = std::to_string(s_.convert.brick_edge);
            side["param.iso"] = fmt("%.17g", iso);
            side["param.projection"] = to_string(s_.mode);
            side["param.radius_scale"] = fmt("%.17g", s_.sampling.radius_scale);
            const std::string ply = base_ + "_iso" + iso_name + ".ply", mlp = base_ + "_iso" + iso_name + ".mlp";
            Sidecar ply_side = side, mlp_side = side;
            ply_side["kind"] = "ply-points";
            mlp_side["kind"] = "point-stream";
            const bool do_ply = s_.ply && !up_to_date(ply, ply_side);
            const bool do_mlp = s_.stream && !up_to_date(mlp, mlp_side);
            r.current += (s_.ply && !do_ply) + (s_.stream && !do_mlp);
            if (!s_.ply && !s_.stream) continue;
            if (!store) {  // the store's index says which isovalues give empty point sets, done or up to date
                store = BrickStore::open(mlb);
                cache = std::make_unique<BrickCache>(*store, s_.memory);
                index = std::make_unique<BrickIndex>(*store);
            }
            r.empty += index->active(iso).empty();
            if (!do_ply && !do_mlp) continue;
            const std::uint32_t c = crc();
            progress_.show("iso " + iso_name);
            const auto& si = store->info();
            if (cb_.iso_range) cb_.iso_range(iso, {si.value_min, si.value_max}, item_.path);
            StreamMeta meta = volume_meta(mlb, si.grid, si.type, {si.value_min, si.value_max}, iso,
                                          "meshless isosurface " + fs::path(mlb).filename().string() + " --iso " +
                                              iso_name + " --projection " + to_string(s_.mode));
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
                std::optional<TeeSink> tee;  // both formats: the PLY first, as it commits first
                if (ply_sink && mlp_sink) tee.emplace(*ply_sink, *mlp_sink);
                Sink& sink = tee ? static_cast<Sink&>(*tee) : ply_sink ? static_cast<Sink&>(*ply_sink) : *mlp_sink;
                run_isosplat_bricks(*store, *cache, index->active(iso), iso, s_.mode, s_.sampling, sink, {s_.threads});
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
        s["meshless"] = std::string(meshless_version()) + " (brick store v" + std::to_string(kBrickStoreVersion) +
                        ", point stream v" + std::to_string(kStreamVersion) + ", readers r" + std::to_string(kReadersRevision) + ")";
        s["param.raw"] = item_.raw_text;
        return s;
    }

    /// The input's CRC-32: from a sidecar whose stat list equals the current one (unless rehash),
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

    const BatchSettings& s_;
    const BatchItem& item_;
    const BatchCallbacks& cb_;
    ProgressReport& progress_;
    std::string base_;
    std::vector<FileStat> stats_;
    std::optional<std::uint32_t> crc_;
};

/// Every output (and sidecar) the items will write; an item whose outputs another item already
/// claims gets an error instead (reported, nothing written for it).
std::vector<std::string> plan_outputs(const BatchSettings& s, std::vector<BatchItem>& items) {
    std::vector<std::string> planned;
    std::map<std::string, std::string> owner;  // output name -> input that claimed it
    for (auto& it : items) {
        if (!it.error.empty()) continue;
        if (auto [pos, fresh] = owner.emplace(it.name, it.path); !fresh) {
            it.error = it.path + ": its outputs would be named '" + it.name + "', like those of " + pos->second;
            continue;
        }
        for (const auto& o : item_outputs(s, it.name)) {
            planned.push_back(o);
            planned.push_back(sidecar_path(o));
        }
    }
    return planned;
}

/// One volume's run, its failure classified: a full disk sets stops_run.
BatchItemResult run_item(const BatchSettings& s, const BatchItem& item, const BatchCallbacks& cb, ProgressReport& progress) {
    BatchItemResult r;
    r.name = item.name;
    const auto t = Clock::now();
    try {
        ItemRunner(s, item, cb, progress).run(r);
        r.status = r.written > 0 ? BatchStatus::done : BatchStatus::up_to_date;
    } catch (const BrokenPipe&) {
        throw;
    } catch (const ReferenceRefused& e) {  // a reference out of the archive: nothing read or written for it
        r.status = BatchStatus::refused;
        r.message = e.what();
    } catch (const std::bad_alloc&) {
        r.message = "out of memory";
    } catch (const std::exception& e) {
        r.message = e.what();
    }
    r.seconds = std::chrono::duration<double>(Clock::now() - t).count();
    if (r.status == BatchStatus::failed) {
        if (is_file_too_large(r.message))
            r.message += "; over the file size limit (ulimit -f, or the file system's largest file); "
                         "temporaries removed";
        if (is_disk_full(r.message)) r.stops_run = "out of disk space in " + s.out_dir;
    }
    return r;
}

}  // namespace

std::string batch_iso_name(double iso) { return fmt("%.9g", iso); }

bool BatchRun::any_empty() const {
    return std::any_of(items.begin(), items.end(), [](const BatchItemResult& r) { return r.empty > 0; });
}

bool BatchRun::any_failed() const {
    return std::any_of(items.begin(), items.end(),
                       [](const BatchItemResult& r) { return r.status == BatchStatus::failed || r.status == BatchStatus::refused; });
}

BatchRun run_batch(const std::string& archive, const BatchSettings& s, const BatchCallbacks& cb) {
    std::error_code ec;
    const bool is_dir = fs::is_directory(archive, ec);
    if (!is_dir && !fs::exists(archive, ec)) throw IoError(archive + ": no such archive folder or manifest");
    if (!is_dir && looks_like_volume(archive))
        throw InvalidArgument(archive + " is a volume; give a folder of volumes or a manifest (one path per line)");
    make_output_folder(s.out_dir);
    const BatchDirLock lock(s.out_dir, s.shard, s.shards);

    const std::vector<BatchItem> archive_items =
        is_dir ? list_archive_dir(archive, s.recursive, s.out_dir) : read_manifest(archive, cb.parse_raw);
    // a shard's volumes, known now; or (a dynamic deal) the whole archive by size, dealt as the run goes
    std::vector<BatchItem> items = s.deal ? archive_items : shard_items(archive_items, s.shard, s.shards);
    const std::vector<std::size_t> by_size = s.deal ? size_order(archive_items) : std::vector<std::size_t>{};
    // every rank of a deal plans the whole archive (the same names collide everywhere); stale temporaries:
    // a shard sweeps its own (the others may be running), a deal's shard 0 the archive's before its first deal
    const std::vector<std::string> planned = plan_outputs(s, items);
    if (!s.deal || s.shard == 0) remove_stale_temporaries(planned, false);

    const auto t0 = Clock::now();
    BatchRun run;
    run.archive_count = archive_items.size();
    run.shard = s.shard;
    run.shards = s.shards;
    std::string disk_full;
    ProgressReport progress(cb.progress, items, s.deal ? s.dealt_share : std::function<double()>{});
    std::size_t next = 0;
    auto next_item = [&]() -> std::optional<std::size_t> {
        if (!s.deal) return next < items.size() ? std::optional<std::size_t>(next++) : std::nullopt;
        const std::optional<std::size_t> pos = s.deal();
        if (pos && *pos >= by_size.size())
            throw std::logic_error("batch: the deal gave volume " + std::to_string(*pos) + " of " + std::to_string(by_size.size()));
        return pos ? std::optional<std::size_t>(by_size[*pos]) : std::nullopt;
    };
    while (const std::optional<std::size_t> i = next_item()) {
        if (!disk_full.empty()) {
            BatchItemResult r;
            r.name = items[*i].name;
            r.message = "not attempted: " + disk_full;
            run.items.push_back(std::move(r));
            continue;
        }
        progress.start_item(*i, items[*i].name);
        BatchItemResult r = run_item(s, items[*i], cb, progress);
        progress.finish_item();
        disk_full = r.stops_run;
        if (cb.item_done) cb.item_done(r);
        run.items.push_back(std::move(r));
    }
    run.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return run;
}

}  // namespace meshless
