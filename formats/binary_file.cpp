#include "formats/binary_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

FilePtr open_regular(const std::string& path) {
    require_regular_file(path);
    FilePtr f(std::fopen(path.c_str(), "rb"));
    if (!f) throw IoError(path + ": cannot open: " + std::strerror(errno));
    return f;
}
}  // namespace

namespace {
std::string not_regular_file(const std::string& path, unsigned mode) {
    if (S_ISFIFO(mode)) return path + ": not a regular file (a FIFO; to read from a pipe, give - for standard input)";
    return path + ": not a regular file (" + (S_ISSOCK(mode) ? "a socket" : "a device") + ")";
}
}  // namespace

void require_regular_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
    if (S_ISDIR(st.st_mode)) throw IoError(path + ": is a directory, expected a file");
    throw IoError(not_regular_file(path, st.st_mode));
}

std::uint64_t regular_file_size(const std::string& path) {
    require_regular_file(path);
    std::error_code ec;
    const auto s = std::filesystem::file_size(path, ec);
    if (ec) throw IoError(path + ": cannot open: " + ec.message());
    return s;
}

FileRangeReader::FileRangeReader(const std::string& path) : path_(path) {
    // O_NONBLOCK: a FIFO is refused below instead of blocking the open (no effect on regular files)
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd_ < 0) throw IoError(path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    std::string why;
    if (::fstat(fd_, &st) != 0) why = path + ": cannot open: " + std::strerror(errno);
    else if (S_ISDIR(st.st_mode)) why = path + ": is a directory, expected a file";
    else if (!S_ISREG(st.st_mode)) why = not_regular_file(path, st.st_mode);
    if (!why.empty()) {
        ::close(fd_);
        throw IoError(why);
    }
    size_ = static_cast<std::uint64_t>(st.st_size);
    // back to blocking reads (some file systems, FUSE among them, pass O_NONBLOCK on to reads)
    const int flags = ::fcntl(fd_, F_GETFL);
    if (flags >= 0) (void)::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
}

FileRangeReader::~FileRangeReader() {
    if (fd_ >= 0) ::close(fd_);
}

void FileRangeReader::read_into(std::uint64_t offset, std::uint64_t count, std::byte* dst) const {
    if (offset > size_ || count > size_ - offset)
        throw FormatError(path_ + ": truncated: need " + std::to_string(count) + " bytes at offset " +
                          std::to_string(offset) + ", file has " + std::to_string(size_));
    std::uint64_t done = 0;
    while (done < count) {
        const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(count - done, std::uint64_t{1} << 30));
        const ssize_t got = ::pread(fd_, dst + done, want, static_cast<off_t>(offset + done));
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0)
            throw IoError(path_ + ": read failed at offset " + std::to_string(offset + done) + ": " +
                          (got < 0 ? std::strerror(errno) : "unexpected end of file"));
        done += static_cast<std::uint64_t>(got);
    }
}

void read_file_range_into(const std::string& path, std::uint64_t offset, std::uint64_t count, std::byte* dst) {
    FileRangeReader(path).read_into(offset, count, dst);
}

std::vector<std::byte> read_file_range(const std::string& path, std::uint64_t offset, std::uint64_t count) {
    const FileRangeReader r(path);
    // validate before allocating (a corrupt header can ask for absurd sizes)
    if (offset > r.size() || count > r.size() - offset)
        throw FormatError(path + ": truncated: need " + std::to_string(count) + " bytes at offset " +
                          std::to_string(offset) + ", file has " + std::to_string(r.size()));
    std::vector<std::byte> out(static_cast<std::size_t>(count));
    r.read_into(offset, count, out.data());
    return out;
}

std::vector<std::byte> read_file_bytes(const std::string& path) {
    const FileRangeReader r(path);
    std::vector<std::byte> out(static_cast<std::size_t>(r.size()));
    r.read_into(0, r.size(), out.data());
    return out;
}

std::string read_file_prefix(const std::string& path, std::size_t max_bytes) {
    FilePtr f = open_regular(path);
    std::string s(max_bytes, '\0');
    const std::size_t got = std::fread(s.data(), 1, max_bytes, f.get());
    if (std::ferror(f.get())) throw IoError(path + ": read failed: " + std::strerror(errno));
    s.resize(got);
    return s;
}

bool file_starts_with(const std::string& path, std::string_view magic) noexcept {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the open
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    std::string head(magic.size(), '\0');
    const ssize_t r = ::pread(fd, head.data(), head.size(), 0);
    ::close(fd);
    return r == static_cast<ssize_t>(magic.size()) && head == magic;
}

}  // namespace meshless
