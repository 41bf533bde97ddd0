#include "formats/point_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "formats/binary_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

void pread_all(int fd, const std::string& path, void* dst, std::size_t n, std::uint64_t offset) {
    std::size_t done = 0;
    auto* d = static_cast<unsigned char*>(dst);
    while (done < n) {
        const ssize_t r = ::pread(fd, d + done, n - done, static_cast<off_t>(offset + done));
        if (r < 0) {
            if (errno == EINTR) continue;
            throw IoError(path + ": read failed at offset " + std::to_string(offset + done) + " (" + std::strerror(errno) + ")");
        }
        if (r == 0) throw FormatError(path + ": truncated point store (the file ends at offset " + std::to_string(offset + done) + ")");
        done += static_cast<std::size_t>(r);
    }
}

long long mtime_ns(const struct stat& st) { return static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec; }

}  // namespace

PointStore::~PointStore() {
    if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<PointStore> PointStore::open(const std::string& path) {
    std::unique_ptr<PointStore> s(new PointStore());
    s->path_ = path;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a point store (.mlc)");
    require_regular_file(path);
    s->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (s->fd_ < 0) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(s->fd_, &st) != 0) throw IoError(path + ": cannot stat (" + std::strerror(errno) + ")");
    s->size_ = static_cast<long long>(st.st_size);
    s->mtime_ns_ = mtime_ns(st);
    const int fd = s->fd_;
    s->layout_ = decode_point_store_layout(
        [&](void* dst, std::size_t n, std::uint64_t off) { pread_all(fd, path, dst, n, off); },
        static_cast<std::uint64_t>(st.st_size), path);
    return s;
}

void PointStore::check_unchanged(std::size_t i) const {
    struct stat st {};
    if (::fstat(fd_, &st) != 0) throw IoError(path_ + ": cannot stat (" + std::strerror(errno) + ")");
    if (static_cast<long long>(st.st_size) != size_ || mtime_ns(st) != mtime_ns_)
        throw FormatError(path_ + ": " + point_brick_where(layout_, i) +
                          ": the file changed while it was read (size or modification time differs from when it was opened)");
}

void PointStore::read_brick(std::size_t i, std::vector<double>& out) const {
    const PointBrickEntry& e = layout_.bricks.at(i);
    check_unchanged(i);
    std::vector<unsigned char> frame(static_cast<std::size_t>(e.stored_bytes));  // <= the file size (checked at open)
    try {
        pread_all(fd_, path_, frame.data(), frame.size(), e.offset);
    } catch (const FormatError&) {
        throw FormatError(path_ + ": " + point_brick_where(layout_, i) + ": truncated (the file ends inside the brick)");
    }
    decode_point_brick(layout_, i, frame, out, path_);
    check_unchanged(i);  // a rewrite during this read: the bytes may mix two versions
}

bool is_point_store(const std::string& path) { return file_starts_with(path, std::string_view(kPointStoreMagic, 8)); }

PointSet point_set_from_point_store(const std::string& path, std::vector<std::string>* notes) {
    const auto store = PointStore::open(path);
    const PointStoreInfo& in = store->info();
    if (notes) {
        notes->push_back("bricks: " + std::to_string(in.brick_count) + " of at most " + std::to_string(in.brick_points) +
                         " points (Morton level " + std::to_string(in.level) + ", zstd level " + std::to_string(in.zstd_level) + ")");
        notes->push_back("dropped at conversion: " + std::to_string(in.dropped_nonfinite) + " NaN/Inf");
        if (!in.source.empty()) notes->push_back("converted from: " + in.source);
    }
    PointSet ps;
    std::vector<double> pts;
    for (std::size_t i = 0; i < store->bricks().size(); ++i) {
        store->read_brick(i, pts);
        for (std::size_t k = 0; k < pts.size(); k += 4) {
            ps.pos.push_back(Vec3{pts[k], pts[k + 1], pts[k + 2]});
            ps.value.push_back(pts[k + 3]);
        }
    }
    ps.value_name = in.value_name;
    ps.has_values = in.has_values;
    ps.dropped_nonfinite = in.dropped_nonfinite;
    ps.dropped_blanked = in.dropped_blanked;
    ps.blocks.push_back(PointSetBlock{std::filesystem::path(path).filename().string(),
                                      {static_cast<std::int64_t>(ps.pos.size()), 1, 1}, 0, ps.pos.size()});
    return ps;
}

}  // namespace meshless
