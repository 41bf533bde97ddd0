#include "ooc/point_store_writer.hpp"

#include <fcntl.h>
#include <unistd.h>
#define ZSTD_STATIC_LINKING_ONLY  // ZSTD_estimateCCtxSize (the budget)
#include <zstd.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <filesystem>
#include <limits>
#include <memory>
#include <queue>

#include "formats/spool_file.hpp"
#include "formats/atomic_file.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/temporary_files.hpp"
#include "formats/terminal_safe.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

struct Rec {
    std::uint64_t key, seq;
    double x, y, z, v;
};
static_assert(sizeof(Rec) == 48);

bool before(const Rec& a, const Rec& b) { return a.key < b.key || (a.key == b.key && a.seq < b.seq); }

constexpr std::uint64_t kFixedBytes = 8ull << 20;   ///< reader chunks and buffers, PLY reader, output buffer
constexpr std::uint64_t kMinRunBuffer = 1024;       ///< records per run in a merge (48 KiB)

/// Unsorted and sorted records spilled to a SpoolFile ("<out>.tmp-<pid>.spool"), counted in records.
class Spool {
public:
    explicit Spool(const std::string& out) : file_(out) {}
    /// Appends n records; returns the record index of the first.
    std::uint64_t append(const Rec* r, std::size_t n) { return file_.append(r, n * sizeof(Rec)) / sizeof(Rec); }
    void read(std::uint64_t at, std::size_t n, Rec* dst) const { file_.read(at * sizeof(Rec), n * sizeof(Rec), dst); }

private:
    SpoolFile file_;
};

/// Records in (key, seq) order, one at a time.
class SortedSource {
public:
    virtual ~SortedSource() = default;
    virtual bool next(Rec& r) = 0;
};

class MemorySource : public SortedSource {
public:
    explicit MemorySource(const std::vector<Rec>& v) : v_(v) {}
    bool next(Rec& r) override {
        if (i_ == v_.size()) return false;
        r = v_[i_++];
        return true;
    }

private:
    const std::vector<Rec>& v_;
    std::size_t i_ = 0;
};

struct Run {
    std::uint64_t first = 0, count = 0;  ///< records in the spool
};

/// k-way merge of sorted runs of the spool, each read through a buffer of `buffer` records.
class MergeSource : public SortedSource {
public:
    MergeSource(const Spool& spool, std::vector<Run> runs, std::size_t buffer) : spool_(spool), runs_(std::move(runs)) {
        bufs_.resize(runs_.size());
        pos_.assign(runs_.size(), 0);
        read_.assign(runs_.size(), 0);
        for (std::size_t i = 0; i < runs_.size(); ++i) {
            bufs_[i].resize(buffer);
            bufs_[i].resize(0);
            refill(i);
            if (!bufs_[i].empty()) heap_.push(i);
        }
    }
    bool next(Rec& r) override {
        if (heap_.empty()) return false;
        const std::size_t i = heap_.top();
        heap_.pop();
        r = bufs_[i][pos_[i]++];
        if (pos_[i] == bufs_[i].size()) refill(i);
        if (pos_[i] < bufs_[i].size()) heap_.push(i);
        return true;
    }

private:
    void refill(std::size_t i) {
        const std::uint64_t left = runs_[i].count - read_[i];
        const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, bufs_[i].capacity()));
        bufs_[i].resize(n);
        if (n) spool_.read(runs_[i].first + read_[i], n, bufs_[i].data());
        read_[i] += n;
        pos_[i] = 0;
    }
    struct Later {
        const MergeSource* m;
        bool operator()(std::size_t a, std::size_t b) const {
            return before(m->bufs_[b][m->pos_[b]], m->bufs_[a][m->pos_[a]]);
        }
    };
    const Spool& spool_;
    std::vector<Run> runs_;
    std::vector<std::vector<Rec>> bufs_;
    std::vector<std::size_t> pos_;
    std::vector<std::uint64_t> read_;
    std::priority_queue<std::size_t, std::vector<std::size_t>, Later> heap_{Later{this}};
};

struct CCtxDeleter {
    void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};
using CCtxPtr = std::unique_ptr<ZSTD_CCtx, CCtxDeleter>;

struct PendingBrick {
    PointBrickEntry entry;
    std::vector<double> raw;  ///< count x 4
    std::vector<unsigned char> frame;
};

std::uint64_t brick_batch_bytes(const PointStoreParams& p, std::size_t batch) {
    const std::uint64_t raw = std::uint64_t{p.brick_points} * kPointStoreRecordBytes;
    return batch * (raw + ZSTD_compressBound(raw)) + static_cast<std::uint64_t>(p.threads) * ZSTD_estimateCCtxSize(p.zstd_level) +
           (std::uint64_t{p.brick_points} + 1) * sizeof(Rec);
}

void check_params(const PointStoreParams& p) {
    if (p.brick_points < 1 || p.brick_points > kPointStoreMaxBrickPoints)
        throw InvalidArgument("--brick-points: expected 1.." + std::to_string(kPointStoreMaxBrickPoints) + ", got " +
                              std::to_string(p.brick_points));
    if (p.zstd_level < 1 || p.zstd_level > ZSTD_maxCLevel())
        throw InvalidArgument("--level: zstd level must be 1.." + std::to_string(ZSTD_maxCLevel()) + ", got " +
                              std::to_string(p.zstd_level));
    if (p.threads < 1) throw InvalidArgument("--threads: must be at least 1");
    if (p.level < 1 || p.level > kPointStoreMaxLevel) throw InvalidArgument("Morton level must be 1..21");
}

std::string human_bytes(std::uint64_t b) {
    char buf[64];
    if (b >= (1ull << 20)) std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(b) / (1 << 20));
    else std::snprintf(buf, sizeof buf, "%.1f KiB", static_cast<double>(b) / 1024);
    return buf;
}

}  // namespace

std::uint64_t point_store_min_memory(const PointStoreParams& p) {
    const std::uint64_t records = std::max<std::uint64_t>(4 * (std::uint64_t{p.brick_points} + 1), 4 * kMinRunBuffer);
    return kFixedBytes + brick_batch_bytes(p, 1) + records * sizeof(Rec) * 3 / 2;
}

PointStoreStats convert_points_to_point_store(const PointChunkProducer& produce, const std::string& source,
                                              const std::string& out_path, const PointStoreParams& p,
                                              const PointStoreProgress& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    check_params(p);
    if (p.memory_bytes < point_store_min_memory(p))
        throw InvalidArgument("--memory: " + human_bytes(p.memory_bytes) + " is too small for bricks of " +
                              std::to_string(p.brick_points) + " points; at least " +
                              human_bytes(point_store_min_memory(p)) + " is needed (or fewer --brick-points)");
    // the brick batch: two bricks per thread when the budget allows, else one brick
    std::size_t batch = static_cast<std::size_t>(p.threads) * 2;
    while (batch > 1 && p.memory_bytes < point_store_min_memory(p) + brick_batch_bytes(p, batch)) batch = 1;
    const std::uint64_t record_budget = p.memory_bytes - kFixedBytes - brick_batch_bytes(p, batch);
    // a growing vector briefly holds its old and new buffers (1.5x its final size)
    const std::size_t cap = static_cast<std::size_t>(record_budget * 2 / 3 / sizeof(Rec));
    const std::uint32_t B = p.brick_points;

    remove_stale_temporaries(out_path);
    std::unique_ptr<Spool> spool;
    std::vector<Rec> recs;
    std::uint64_t seq = 0, spilled = 0;
    std::array<double, 3> lo{}, hi{};
    double vmin = 0, vmax = 0;
    // 1. read
    const PointChunkTotals totals = produce([&](std::span<const double> xyzv) {
        for (std::size_t k = 0; k + 3 < xyzv.size(); k += 4) {
            const Rec r{0, seq, xyzv[k], xyzv[k + 1], xyzv[k + 2], xyzv[k + 3]};
            if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z) || !std::isfinite(r.v))
                throw InvalidArgument("point store conversion: non-finite point handed over");  // the producer drops them
            if (seq == 0) {
                lo = hi = {r.x, r.y, r.z};
                vmin = vmax = r.v;
            } else {
                lo = {std::min(lo[0], r.x), std::min(lo[1], r.y), std::min(lo[2], r.z)};
                hi = {std::max(hi[0], r.x), std::max(hi[1], r.y), std::max(hi[2], r.z)};
                vmin = std::min(vmin, r.v);
                vmax = std::max(vmax, r.v);
            }
            ++seq;
            if (recs.size() == cap) {
                if (!spool) spool = std::make_unique<Spool>(out_path);
                spool->append(recs.data(), recs.size());
                spilled += recs.size();
                recs.clear();
            }
            if (recs.size() == recs.capacity()) recs.reserve(std::min(cap, std::max<std::size_t>(1024, recs.capacity() * 2)));
            recs.push_back(r);
        }
        if (progress) progress("read", seq, 0);
    });
    const std::uint64_t n = seq;
    if (n < kMinPointSetPoints)
        throw FormatError(source + ": " + std::to_string(n) + " valid point" + (n == 1 ? "" : "s") + " (" +
                          std::to_string(totals.dropped_nonfinite) + " NaN/Inf dropped), at least " +
                          std::to_string(kMinPointSetPoints) + " needed");
    for (int a = 0; a < 3; ++a)
        if (!(hi[a] - lo[a] <= kPointStoreMaxExtent))
            throw FormatError(source + ": the points' " + "xyz"[a] + " coordinates span more than 1e150 units (squared distances would overflow)");

    const PointStoreGrid grid(lo, hi, p.level);
    tbb::task_arena arena(p.threads);
    auto key_and_sort = [&](std::vector<Rec>& v) {
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, v.size(), 65536), [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t i = r.begin(); i < r.end(); ++i) v[i].key = grid.key(v[i].x, v[i].y, v[i].z);
            });
            tbb::parallel_sort(v.begin(), v.end(), before);
        });
    };

    // 2. sort
    PointStoreStats st;
    std::unique_ptr<SortedSource> sorted;
    if (!spool) {
        key_and_sort(recs);
        sorted = std::make_unique<MemorySource>(recs);
    } else {
        spool->append(recs.data(), recs.size());
        spilled += recs.size();
        std::vector<Run> runs;
        for (std::uint64_t r0 = 0; r0 < spilled; r0 += cap) {
            const std::size_t m = static_cast<std::size_t>(std::min<std::uint64_t>(cap, spilled - r0));
            recs.resize(m);
            spool->read(r0, m, recs.data());
            key_and_sort(recs);
            runs.push_back(Run{spool->append(recs.data(), m), m});
            if (progress) progress("sort", runs.size(), (spilled + cap - 1) / cap);
        }
        std::vector<Rec>().swap(recs);
        st.runs = runs.size();
        const std::size_t fanout = std::max<std::size_t>(2, cap / kMinRunBuffer);
        while (runs.size() > fanout) {  // intermediate passes: groups of `fanout` runs into one
            ++st.merge_passes;
            std::vector<Run> next;
            const std::size_t per = cap / (fanout + 1);
            for (std::size_t g = 0; g < runs.size(); g += fanout) {
                std::vector<Run> group(runs.begin() + static_cast<std::ptrdiff_t>(g),
                                       runs.begin() + static_cast<std::ptrdiff_t>(std::min(runs.size(), g + fanout)));
                MergeSource m(*spool, group, per);
                std::vector<Rec> out;
                out.reserve(per);
                Run merged{0, 0};
                Rec r;
                bool first = true;
                auto flush = [&] {
                    const std::uint64_t at = spool->append(out.data(), out.size());
                    if (first) merged.first = at;
                    first = false;
                    merged.count += out.size();
                    out.clear();
                };
                while (m.next(r)) {
                    out.push_back(r);
                    if (out.size() == per) flush();
                }
                if (!out.empty() || first) flush();
                next.push_back(merged);
            }
            runs.swap(next);
        }
        sorted = std::make_unique<MergeSource>(*spool, runs, cap / runs.size());
    }

    // 3. bricks
    PointStoreInfo info;
    info.points = n;
    info.dropped_nonfinite = totals.dropped_nonfinite;
    info.dropped_blanked = totals.dropped_blanked;
    info.lo = lo;
    info.hi = hi;
    info.value_min = vmin;
    info.value_max = vmax;
    info.level = p.level;
    info.brick_points = B;
    info.zstd_level = p.zstd_level;
    info.has_values = totals.has_values;
    info.value_name = totals.value_name.substr(0, kPointStoreValueNameBytes - 1);
    info.source = source.substr(0, kPointStoreSourceBytes - 1);

    AtomicFile file(out_path, Durability::fsync);
    const std::array<unsigned char, kPointStoreHeaderBytes> blank{};
    file.write(blank.data(), blank.size());  // the header is written last
    std::uint64_t at = kPointStoreHeaderBytes, first = 0;
    std::vector<PointBrickEntry> index;
    std::vector<PendingBrick> pending(batch);
    std::size_t npending = 0;
    tbb::enumerable_thread_specific<CCtxPtr> cctx([] { return CCtxPtr(ZSTD_createCCtx()); });
    auto flush_batch = [&] {
        arena.execute([&] {
            tbb::parallel_for(std::size_t{0}, npending, [&](std::size_t i) {
                ZSTD_CCtx* cc = cctx.local().get();
                if (!cc) throw std::bad_alloc();
                PendingBrick& b = pending[i];
                const std::size_t raw = b.raw.size() * sizeof(double);
                b.frame.resize(ZSTD_compressBound(raw));
                const std::size_t z = ZSTD_compressCCtx(cc, b.frame.data(), b.frame.size(), b.raw.data(), raw, p.zstd_level);
                if (ZSTD_isError(z)) throw IoError(out_path + ": zstd compression failed (" + ZSTD_getErrorName(z) + ")");
                b.frame.resize(z);
                b.entry.crc = point_store_crc32(b.frame.data(), z);
                b.entry.stored_bytes = z;
            });
        });
        for (std::size_t i = 0; i < npending; ++i) {
            PendingBrick& b = pending[i];
            b.entry.offset = at;
            file.write(b.frame.data(), b.frame.size());
            at += b.frame.size();
            index.push_back(b.entry);
        }
        if (progress) progress("write", first, n);
        npending = 0;
    };

    std::deque<Rec> la;  // lookahead: B + 1 records
    bool more = true, have_prev = false;
    std::uint64_t prev = 0;
    Rec r;
    const std::uint32_t L = p.level;
    for (;;) {
        while (more && la.size() < std::size_t{B} + 1) {
            if (sorted->next(r)) la.push_back(r);
            else more = false;
        }
        if (la.empty()) break;
        const std::uint64_t k0 = la.front().key;
        std::uint32_t d = 0;
        std::uint64_t end = 0;
        for (;; ++d) {
            const unsigned shift = 3 * (L - d);
            const std::uint64_t s = (k0 >> shift) << shift;
            end = s + (std::uint64_t{1} << shift);
            if (d == L) break;
            if ((!have_prev || s > prev) && (la.size() <= B || la[B].key >= end)) break;
        }
        PendingBrick& b = pending[npending];
        PointBrickEntry& e = b.entry;
        e = PointBrickEntry{};
        e.level = d;
        e.key = k0 >> (3 * (L - d));
        e.first = first;
        b.raw.clear();
        while (!la.empty() && la.front().key < end && e.count < B) {
            const Rec& q = la.front();
            if (e.count == 0) {
                e.lo = e.hi = {q.x, q.y, q.z};
                e.vmin = e.vmax = q.v;
            } else {
                e.lo = {std::min(e.lo[0], q.x), std::min(e.lo[1], q.y), std::min(e.lo[2], q.z)};
                e.hi = {std::max(e.hi[0], q.x), std::max(e.hi[1], q.y), std::max(e.hi[2], q.z)};
                e.vmin = std::min(e.vmin, q.v);
                e.vmax = std::max(e.vmax, q.v);
            }
            b.raw.insert(b.raw.end(), {q.x, q.y, q.z, q.v});
            prev = q.key;
            ++e.count;
            la.pop_front();
        }
        have_prev = true;
        first += e.count;
        if (++npending == batch) flush_batch();
    }
    if (npending) flush_batch();
    sorted.reset();
    spool.reset();  // the spool is no longer needed: its disk space back before the fsync
    info.brick_count = index.size();

    std::vector<unsigned char> idx(index.size() * kPointStoreEntryBytes);
    for (std::size_t i = 0; i < index.size(); ++i) encode_point_brick_entry(index[i], idx.data() + i * kPointStoreEntryBytes);
    file.write(idx.data(), idx.size());
    const auto footer = encode_point_store_footer(at, index.size(), point_store_crc32(idx.data(), idx.size()));
    file.write(footer.data(), footer.size());
    const auto header = encode_point_store_header(info);
    file.pwrite(0, header.data(), header.size());
    file.commit();

    st.points = n;
    st.dropped_nonfinite = totals.dropped_nonfinite;
    st.dropped_blanked = totals.dropped_blanked;
    st.bricks = index.size();
    st.output_bytes = at + idx.size() + footer.size();
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return st;
}

PointStoreStats convert_to_point_store(const std::vector<std::string>& paths, const PointSetOptions& options,
                                       const std::string& out_path, const PointStoreParams& params,
                                       const PointStoreProgress& progress) {
    std::string source;
    for (const std::string& s : paths) source += (source.empty() ? "" : " ") + std::filesystem::path(s).filename().string();
    return convert_points_to_point_store(
        [&](const std::function<void(std::span<const double>)>& chunk) { return stream_point_set(paths, options, chunk); },
        source, out_path, params, progress);
}

std::string point_store_stats_line(const PointStoreStats& st, const std::string& output, std::uint32_t brick_points) {
    char head[128], tail[256];
    std::snprintf(head, sizeof head, "convert: %llu points (%llu NaN/Inf dropped) -> ", static_cast<unsigned long long>(st.points),
                  static_cast<unsigned long long>(st.dropped_nonfinite));
    std::snprintf(tail, sizeof tail, ": %llu bricks of at most %u points, %llu sorted run%s spilled, %.1f MB in %.3f s",
                  static_cast<unsigned long long>(st.bricks), brick_points, static_cast<unsigned long long>(st.runs),
                  st.runs == 1 ? "" : "s", static_cast<double>(st.output_bytes) / 1e6, st.seconds);
    return head + terminal_safe(output) + tail;
}

}  // namespace meshless
