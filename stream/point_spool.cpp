#include "stream/point_spool.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

PointSpool::PointSpool(const std::string& purpose) {
    const char* dir = std::getenv("TMPDIR");
    std::string tmpl = std::string(dir && *dir ? dir : "/tmp") + "/meshless-" + purpose + "-XXXXXX";
    const int fd = ::mkstemp(tmpl.data());
    if (fd < 0) throw IoError(tmpl + ": cannot create the temporary point spool: " + std::strerror(errno));
    name_ = tmpl;
    ::unlink(name_.c_str());  // unlinked: the space is freed whatever happens to the process
    f_ = ::fdopen(fd, "w+b");
    if (!f_) {
        const int e = errno;
        ::close(fd);
        throw IoError(name_ + ": cannot open the temporary point spool: " + std::strerror(e));
    }
}

PointSpool::~PointSpool() {
    if (f_) std::fclose(f_);
}

void PointSpool::fail(const char* what, int err) const {
    throw IoError(name_ + ": cannot " + what + " the point spool (deleted temporary file): " +
                  (err ? std::strerror(err) : "short file"));
}

void PointSpool::append(std::span<const PointRecord> points) {
    if (points.empty()) return;
    errno = 0;
    if (std::fwrite(points.data(), sizeof(PointRecord), points.size(), f_) != points.size()) fail("write to", errno);
    count_ += points.size();
    bounds_.add(points);
}

void PointSpool::observe(const Batch& b) {
    if (b.kind != RecordKind::point)
        throw FormatError("point spool: input holds unprojected samples; run 'meshless project' first");
    append(b.points);
}

void PointSpool::flush() {
    errno = 0;
    if (std::fflush(f_) != 0) fail("write to", errno);
}

void PointSpool::read(std::uint64_t first, std::span<PointRecord> out) const {
    if (first + out.size() > count_)
        throw IoError(name_ + ": cannot read points " + std::to_string(first) + ".." + std::to_string(first + out.size()) +
                      " back from the point spool (deleted temporary file): it holds " + std::to_string(count_));
    const int fd = ::fileno(f_);
    const std::size_t want = out.size() * sizeof(PointRecord);
    char* dst = reinterpret_cast<char*>(out.data());
    std::size_t got = 0;
    while (got < want) {
        const ssize_t r = ::pread(fd, dst + got, want - got, static_cast<off_t>(first * sizeof(PointRecord) + got));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) fail("read back from", r < 0 ? errno : 0);
        got += static_cast<std::size_t>(r);
    }
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
    at_ += n;
    return b;
}

bool PointSpoolSource::recycle(Batch& consumed) {
    std::lock_guard lock(m_);
    if (spare_.capacity() != 0 || consumed.points.capacity() == 0) return false;
    spare_.swap(consumed.points);
    return true;
}

std::size_t PointSpoolSource::retained_bytes() {
    std::lock_guard lock(m_);
    return spare_.capacity() * sizeof(PointRecord);
}

}  // namespace meshless
