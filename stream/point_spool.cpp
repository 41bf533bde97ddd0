#include "stream/point_spool.hpp"
#include "formats/binary_file.hpp"

#include "formats/ply_points.hpp"
#include "formats/temporary_files.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <limits>
#include <cstring>
#include <stdexcept>

#include "kernels/errors.hpp"

namespace meshless {

std::FILE* PointSpool::create(const std::string& purpose, std::string& name) { return unlinked_temporary(purpose, name); }

PointSpool::PointSpool(const std::string& purpose) : purpose_(purpose) { f_ = create(purpose, name_); }

bool PointSpool::can_be_in_place(const std::string& ply_path) {
    try {
        return PlyPointReader(ply_path).records_offset().has_value();
    } catch (const std::exception&) {
        return false;
    }
}

PointSpool::PointSpool(InPlace, const std::string& ply_path, int threads)
    : purpose_("in place"), name_(ply_path), in_place_(true) {
    PlyPointReader r(ply_path);  // the header, its counts against the file's size
    const std::optional<std::uint64_t> at = r.records_offset();
    if (!at) throw FormatError(ply_path + ": not a binary PLY of meshless points (x y z nx ny nz radius value, float): cannot be read in place");
    base_ = *at;
    require_regular_file(ply_path);
    f_ = std::fopen(ply_path.c_str(), "rbe");  // e: close-on-exec, as the readers open files
    if (!f_) throw IoError(ply_path + ": cannot open: " + std::strerror(errno));
    try {
        scan_in_place(r, threads);
    } catch (...) {
        std::fclose(f_);  // the destructor does not run for a constructor that throws
        f_ = nullptr;
        throw;
    }
}

void PointSpool::scan_in_place(PlyPointReader& r, int threads) {
    struct stat st {};
    const std::uint64_t n = r.count();
    if (::fstat(::fileno(f_), &st) != 0 || static_cast<std::uint64_t>(st.st_size) != base_ + n * sizeof(PointRecord)) {
        // not exactly the records the header announces: the reader reports what is wrong
        std::vector<PointRecord> batch;
        while (r.read(batch, kMaxBatchRecords) > 0) tally_.add(batch);
        if (n == 0) r.read(batch, 0);
        count_ = n;
        return;
    }
    count_ = n;  // read() reads [0, n) below
    // one tally per part, merged in part order: the same bits (signed zeros too) for any thread count
    const auto parts = static_cast<std::size_t>((n + kMaxBatchRecords - 1) / kMaxBatchRecords);
    std::vector<Tally> part(parts);
    oneapi::tbb::enumerable_thread_specific<std::vector<PointRecord>> batches;
    auto scan = [&](std::size_t i) {
        std::vector<PointRecord>& batch = batches.local();
        const std::uint64_t first = i * kMaxBatchRecords;
        batch.resize(static_cast<std::size_t>(std::min<std::uint64_t>(kMaxBatchRecords, n - first)));
        read(first, batch);
        part[i].add(batch);
    };
    if (threads <= 1) {
        for (std::size_t i = 0; i < parts; ++i) scan(i);
    } else {
        oneapi::tbb::task_arena arena(threads);
        arena.execute([&] { oneapi::tbb::parallel_for(std::size_t{0}, parts, scan); });
    }
    for (const Tally& t : part) tally_.merge(t);
}

PointSpool::~PointSpool() {
    if (f_) std::fclose(f_);
    if (blocks_) std::fclose(blocks_);
}

std::optional<std::array<double, 2>> PointSpool::value_range() const {
    if (!tally_.any) return std::nullopt;
    return std::array<double, 2>{tally_.lo, tally_.hi};
}

void PointSpool::fail(const char* what, int err) const {
    throw IoError(name_ + ": cannot " + what + " the point spool (" + kind() + "): " + (err ? std::strerror(err) : "short file"));
}

void PointSpool::Tally::add(std::span<const PointRecord> points) {
    bounds.add(points);
    for (const PointRecord& p : points) undrawable += drawable(p) ? 0 : 1;
    // In float, without branches (as PointBounds::add): a non-finite value offers +inf to the
    // minimum and -inf to the maximum; min and max keep the first of equal values, as the
    // sequential fold did, so the same range, signed zeros included.
    constexpr float inf = std::numeric_limits<float>::infinity();
    float flo = inf, fhi = -inf;
    for (const PointRecord& p : points) {
        const bool ok = std::isfinite(p.value);
        const float l = ok ? p.value : inf, h = ok ? p.value : -inf;
        flo = l < flo ? l : flo;
        fhi = fhi < h ? h : fhi;
    }
    if (!(flo <= fhi)) return;  // no finite value
    lo = any ? std::min<double>(lo, flo) : flo;
    hi = any ? std::max<double>(hi, fhi) : fhi;
    any = true;
}

void PointSpool::Tally::merge(const Tally& o) {
    bounds.merge(o.bounds);
    undrawable += o.undrawable;
    if (!o.any) return;
    lo = any ? std::min(lo, o.lo) : o.lo;
    hi = any ? std::max(hi, o.hi) : o.hi;
    any = true;
}

void PointSpool::append(std::span<const PointRecord> points, std::span<const std::uint32_t> blocks) {
    if (in_place_) throw std::logic_error("PointSpool: " + name_ + " is read in place; nothing can be appended");
    if (points.empty()) return;
    if (!blocks.empty() && blocks.size() != points.size())
        throw FormatError("point spool: " + std::to_string(blocks.size()) + " block ids for " + std::to_string(points.size()) + " points");
    if (count_ == 0 && !blocks.empty()) blocks_ = create(purpose_ + "-blocks", blocks_name_);
    if (blocks.empty() != (blocks_ == nullptr))
        throw FormatError("point spool: points with and without block ids mixed in one input");
    errno = 0;
    if (std::fwrite(points.data(), sizeof(PointRecord), points.size(), f_) != points.size()) fail("write to", errno);
    if (blocks_ && std::fwrite(blocks.data(), sizeof(std::uint32_t), blocks.size(), blocks_) != blocks.size())
        fail("write to", errno);
    count_ += points.size();
    tally_.add(points);
    for (std::uint32_t b : blocks) block_count_ = std::max(block_count_, b == ~std::uint32_t{0} ? b : b + 1);
}

void PointSpool::observe(const Batch& b) {
    append(b.points, b.point_block);
}

void PointSpool::flush() {
    if (in_place_) return;
    errno = 0;
    if (std::fflush(f_) != 0) fail("write to", errno);
    if (blocks_ && std::fflush(blocks_) != 0) fail("write to", errno);
}

void PointSpool::pread_all(std::FILE* f, const std::string& name, char* dst, std::size_t want, std::uint64_t offset,
                           const char* kind) {
    const int fd = ::fileno(f);
    std::size_t got = 0;
    while (got < want) {
        const ssize_t r = ::pread(fd, dst + got, want - got, static_cast<off_t>(offset + got));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0)
            throw IoError(name + ": cannot read back from the point spool (" + kind + "): " + (r < 0 ? std::strerror(errno) : "short file"));
        got += static_cast<std::size_t>(r);
    }
}

void PointSpool::read_blocks(std::uint64_t first, std::span<std::uint32_t> out) const {
    if (!blocks_) throw std::logic_error("PointSpool::read_blocks: the points have no block ids");
    if (first + out.size() > count_)
        throw IoError(blocks_name_ + ": cannot read block ids " + std::to_string(first) + ".." + std::to_string(first + out.size()) +
                      " back from the point spool (deleted temporary file): it holds " + std::to_string(count_));
    pread_all(blocks_, blocks_name_, reinterpret_cast<char*>(out.data()), out.size() * sizeof(std::uint32_t),
              first * sizeof(std::uint32_t), "deleted temporary file");
}

void PointSpool::read(std::uint64_t first, std::span<PointRecord> out) const {
    if (first + out.size() > count_)
        throw IoError(name_ + ": cannot read points " + std::to_string(first) + ".." + std::to_string(first + out.size()) +
                      " back from the point spool (" + kind() + "): it holds " + std::to_string(count_));
    pread_all(f_, name_, reinterpret_cast<char*>(out.data()), out.size() * sizeof(PointRecord),
              base_ + first * sizeof(PointRecord), kind());
}

PointSpoolSource::PointSpoolSource(PointSpool& spool, std::size_t batch_records)
    : spool_(spool), per_(std::clamp<std::size_t>(batch_records, 1, kMaxBatchRecords)) {
    spool.flush();
}

std::optional<Batch> PointSpoolSource::next() {
    if (at_ >= spool_.size()) return std::nullopt;
    const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(per_, spool_.size() - at_));
    Batch b;
    b.seq = seq_++;
    b.kind = RecordKind::point;
    {
        std::lock_guard lock(m_);
        b.points.swap(spare_);
    }
    b.points.resize(n);
    spool_.read(at_, b.points);
    if (spool_.has_blocks()) {
        {
            std::lock_guard lock(m_);
            b.point_block.swap(spare_blocks_);
        }
        b.point_block.resize(n);
        spool_.read_blocks(at_, b.point_block);
    }
    at_ += n;
    return b;
}

bool PointSpoolSource::recycle(Batch& consumed) {
    std::lock_guard lock(m_);
    if (spare_.capacity() != 0 || consumed.points.capacity() == 0) return false;
    spare_.swap(consumed.points);
    if (spare_blocks_.capacity() == 0) spare_blocks_.swap(consumed.point_block);
    return true;
}

std::size_t PointSpoolSource::retained_bytes() {
    std::lock_guard lock(m_);
    return spare_.capacity() * sizeof(PointRecord) + spare_blocks_.capacity() * sizeof(std::uint32_t);
}

}  // namespace meshless
