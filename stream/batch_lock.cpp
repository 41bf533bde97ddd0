#include "stream/batch_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "kernels/errors.hpp"

namespace meshless {

BatchDirLock::BatchDirLock(const std::string& dir) {
    const std::string p = (std::filesystem::path(dir) / ".meshless-batch.lock").string();
    fd_ = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw IoError(p + ": cannot create lock file (" + std::strerror(errno) + ")");
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        ::close(fd_);
        throw IoError(dir + ": another meshless batch is writing to this folder (" + p + " is locked)");
    }
}

BatchDirLock::~BatchDirLock() { ::close(fd_); }

}  // namespace meshless
