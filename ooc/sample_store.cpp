#include "ooc/sample_store.hpp"
#include "formats/binary_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "kernels/iso_threshold.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_store_identity.hpp"

namespace meshless {

namespace {

void pread_all(int fd, void* dst, std::size_t n, std::uint64_t offset, const std::string& path) {
    auto* p = static_cast<char*>(dst);
    while (n > 0) {
        const ssize_t r = ::pread(fd, p, n, static_cast<off_t>(offset));
        if (r < 0) {
            if (errno == EINTR) continue;
            throw IoError(path + ": read failed (" + std::strerror(errno) + ")");
        }
        if (r == 0) throw FormatError(path + ": truncated sample store (unexpected end of file at byte " + std::to_string(offset) + ")");
        p += r;
        n -= static_cast<std::size_t>(r);
        offset += static_cast<std::uint64_t>(r);
    }
}

}  // namespace

SampleStore::~SampleStore() {
    if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<SampleStore> SampleStore::open(const std::string& path) {
    std::unique_ptr<SampleStore> s(new SampleStore());
    s->path_ = path;
    require_regular_file(path);
    s->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (s->fd_ < 0) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    struct stat sb {};
    if (::fstat(s->fd_, &sb) != 0) throw IoError(path + ": cannot stat (" + std::strerror(errno) + ")");
    if (!S_ISREG(sb.st_mode)) throw IoError(path + ": not a regular file");
    const int fd = s->fd_;
    s->layout_ = decode_sample_store_layout([&](void* d, std::size_t n, std::uint64_t o) { pread_all(fd, d, n, o, path); },
                                            static_cast<std::uint64_t>(sb.st_size), path);
    const SampleStoreInfo& info = s->layout_.info;
    s->levels_ = SpanSpaceLevels::from_header(info.value_lo, info.value_hi, info.levels, info.exact_levels);

    // the brick store the samples are recomputed from
    namespace fs = std::filesystem;
    fs::path mlb(info.mlb_path);
    if (mlb.is_relative()) mlb = fs::path(path).parent_path() / mlb;
    const std::string m = mlb.string();
    std::error_code ec;
    if (!fs::exists(mlb, ec))
        throw FormatError(path + ": its brick store " + m + " is missing (a sample store recomputes samples from the .mlb "
                          "it was made from; keep them together or remake it with 'meshless generate VOL.mlb --all -o " + path + "')");
    BrickStoreIdentity id;
    try {
        id = brick_store_identity(m);
    } catch (const FormatError& e) {
        throw FormatError(path + ": its brick store is unusable: " + e.what());
    }
    if (!(id == info.mlb))
        throw FormatError(path + ": its brick store " + m + " has changed since the sample store was made (size or "
                          "checksums differ); remake it with 'meshless generate " + m + " --all -o " + path + "'");
    try {
        s->mlb_ = BrickStore::open(m);
    } catch (const FormatError& e) {
        throw FormatError(path + ": its brick store is unusable: " + e.what());
    }
    const BrickStoreInfo& bi = s->mlb_->info();
    if (!(bi.grid == info.grid) || bi.type != info.type || bi.brick_edge != info.brick_edge ||
        bi.brick_count != info.mlb.brick_count)
        throw FormatError(path + ": grid, type or bricks of " + m + " differ from the sample store's header");
    return s;
}

void SampleStore::read_bytes(void* dst, std::size_t n, std::uint64_t offset) const {
    pread_all(fd_, dst, n, offset, path_);
    key_bytes_read_ += n;
}

SampleStoreStats SampleStore::stats() const {
    SampleStoreStats s;
    s.queries = queries_.load();
    s.buckets_read = buckets_read_.load();
    s.key_bytes_read = key_bytes_read_.load();
    s.rows_read = rows_read_.load();
    s.bricks_read = bricks_read_.load();
    s.samples_emitted = samples_emitted_.load();
    return s;
}

void SampleStore::reset_stats() const {
    queries_ = 0;
    buckets_read_ = 0;
    key_bytes_read_ = 0;
    rows_read_ = 0;
    bricks_read_ = 0;
    samples_emitted_ = 0;
}

std::uint64_t SampleStore::query(double iso, const std::function<void(std::span<const SampleRecord>)>& emit,
                                 const SamplingParams& params, std::size_t max_batch) const {
    SampleQuery q(*this, iso, params);
    std::vector<SampleRecord> out;
    max_batch = std::clamp<std::size_t>(max_batch, 1, 65536);
    while (q.next(out, max_batch)) emit(std::span<const SampleRecord>(out.data(), out.size()));
    return q.emitted();
}

void SampleStore::verify() const {
    std::vector<unsigned char> bytes;
    RowSet rows(layout_.key_limit());
    for (std::size_t i = 0; i < layout_.buckets.size(); ++i) {
        const SampleBucket& b = layout_.buckets[i];
        bytes.resize(b.bytes);
        read_bytes(bytes.data(), bytes.size(), kSampleStoreHeaderBytes + b.offset);
        decode_sample_store_bucket(layout_, i, bytes.data(), &rows, path_);
        ++buckets_read_;
    }
    // every key must name a row inside its brick
    const std::uint64_t B2 = static_cast<std::uint64_t>(info().brick_edge) * info().brick_edge;
    for (std::uint64_t k = rows.next(0); k < rows.limit(); k = rows.next(k + 1))
        if (static_cast<std::int64_t>(k % B2) >= cell_row_count(mlb_->brick_grid(k / B2)))
            throw FormatError(path_ + ": key " + std::to_string(k) + " names a cell row outside its brick (corrupt keys)");
}

// ---------------------------------------------------------------------------------------------
// Query

SampleQuery::SampleQuery(const SampleStore& store, double iso, const SamplingParams& params)
    : store_(store), iso_(iso), params_(params), rows_(store.layout_.key_limit()) {
    if (std::isnan(iso)) throw InvalidArgument("sample store query: the isovalue is NaN");
    const SampleStoreInfo& info = store.info();
    const double thr = active_threshold(info.type, iso);
    const auto& bk = store.layout_.buckets;
    // candidate buckets; those of one row a are a suffix of the row, contiguous on disk
    std::vector<unsigned char> bytes;
    for (std::size_t i = 0; i < bk.size();) {
        if (!store.levels_.candidate(bk[i].a, bk[i].b, thr)) {
            ++i;
            continue;
        }
        std::size_t j = i + 1;
        while (j < bk.size() && store.levels_.candidate(bk[j].a, bk[j].b, thr)) ++j;
        const std::uint64_t first = bk[i].offset, n = bk[j - 1].offset + bk[j - 1].bytes - first;
        bytes.resize(n);
        store.read_bytes(bytes.data(), n, kSampleStoreHeaderBytes + first);
        for (std::size_t k = i; k < j; ++k)
            decode_sample_store_bucket(store.layout_, k, bytes.data() + (bk[k].offset - first), &rows_, store.path_);
        store.buckets_read_ += j - i;
        i = j;
    }
    at_ = rows_.next(0);
    ++store.queries_;
}

bool SampleQuery::next(std::vector<SampleRecord>& result, std::size_t max) {
    // built in a member vector that keeps its capacity, then copied at its exact size: a fresh
    // batch vector per call costs one allocation, not a growth sequence (page faults)
    std::vector<SampleRecord>& out = out_;
    out.clear();
    max = std::max<std::size_t>(max, 1);
    const BrickStore& mlb = *store_.mlb_;
    const std::uint64_t B2 = static_cast<std::uint64_t>(store_.info().brick_edge) * store_.info().brick_edge;
    while (out.size() < max && (pend_at_ < pending_.size() || at_ < rows_.limit())) {
        if (pend_at_ < pending_.size()) {  // records of a row run that did not fit the last batch
            const std::size_t n = std::min(max - out.size(), pending_.size() - pend_at_);
            out.insert(out.end(), pending_.begin() + static_cast<std::ptrdiff_t>(pend_at_),
                       pending_.begin() + static_cast<std::ptrdiff_t>(pend_at_ + n));
            pend_at_ += n;
            continue;
        }
        const std::uint64_t key = at_;
        const std::size_t brick = static_cast<std::size_t>(key / B2);
        // one batch per brick at most (as BrickSource): small batches, reused memory, pipelining
        if (static_cast<std::int64_t>(brick) != brick_ && !out.empty()) break;
        const std::int64_t row = static_cast<std::int64_t>(key % B2);
        GridSpec g = mlb.brick_grid(brick);
        const std::int64_t rows = cell_row_count(g);
        if (row >= rows)
            throw FormatError(store_.path_ + ": a bucket names cell row " + std::to_string(row) + " of brick " +
                              std::to_string(brick) + ", which has " + std::to_string(rows) + " (corrupt keys)");
        if (static_cast<std::int64_t>(brick) != brick_) {
            mlb.read_brick(brick, buf_);
            brick_ = static_cast<std::int64_t>(brick);
            ++store_.bricks_read_;
        }
        // a run of consecutive candidate rows of this brick, as many as fit the batch
        const std::int64_t per_row = std::max<std::int64_t>(1, g.dims[0] - 1);
        const std::int64_t room = std::max<std::int64_t>(1, static_cast<std::int64_t>(max - out.size()) / per_row);
        std::int64_t r1 = row + 1;
        while (r1 < rows && r1 - row < room && rows_.contains(key + static_cast<std::uint64_t>(r1 - row))) ++r1;
        at_ = rows_.next(key + static_cast<std::uint64_t>(r1 - row));
        store_.rows_read_ += static_cast<std::uint64_t>(r1 - row);
        // paradigm (C)'s kernel on these rows, positions from the whole volume (as BrickGenerateStage)
        SamplingParams p = params_;
        p.index_offset = mlb.brick_first_voxel(brick);
        g.origin = store_.info().grid.origin;
        const VolumeView v{buf_.data(), store_.info().type, g};
        SamplingStats st;
        if (static_cast<std::int64_t>(max - out.size()) >= (r1 - row) * per_row) {
            sample_active_cells(v, iso_, row, r1, p, out, st);
        } else {
            pending_.clear();
            pend_at_ = 0;
            sample_active_cells(v, iso_, row, r1, p, pending_, st);
        }
    }
    emitted_ += out.size();
    store_.samples_emitted_ += out.size();
    result.assign(out.begin(), out.end());
    return !out.empty();
}

bool is_sample_store(const std::string& path) { return file_starts_with(path, std::string_view(kSampleStoreMagic, 8)); }

}  // namespace meshless
