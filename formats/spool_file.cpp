#include "formats/spool_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

SpoolFile::SpoolFile(const std::string& out)
    : out_(out), path_(out + ".tmp-" + std::to_string(::getpid()) + ".spool"), registration_(path_) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) throw IoError(out_ + ": cannot create temporary file " + path_ + " (" + std::strerror(errno) + ")");
}

SpoolFile::~SpoolFile() {
    ::close(fd_);
    ::unlink(path_.c_str());
}

std::uint64_t SpoolFile::append(const void* p, std::size_t bytes) {
    const std::uint64_t at = size_;
    const auto* c = static_cast<const char*>(p);
    std::size_t done = 0;
    while (done < bytes) {
        const ssize_t w = ::pwrite(fd_, c + done, bytes - done, static_cast<off_t>(at + done));
        if (w < 0) {
            if (errno == EINTR) continue;
            throw IoError(out_ + ": write failed (temporary file " + path_ + ": " + std::strerror(errno) + ")");
        }
        done += static_cast<std::size_t>(w);
    }
    size_ += bytes;
    return at;
}

void SpoolFile::read(std::uint64_t offset, std::size_t bytes, void* dst) const {
    auto* c = static_cast<char*>(dst);
    std::size_t done = 0;
    while (done < bytes) {
        const ssize_t r = ::pread(fd_, c + done, bytes - done, static_cast<off_t>(offset + done));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) throw IoError(out_ + ": cannot read back temporary file " + path_);
        done += static_cast<std::size_t>(r);
    }
}

}  // namespace meshless
