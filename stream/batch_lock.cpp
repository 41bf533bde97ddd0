#include "stream/batch_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
/// Opens (creating) the lock file `name` in `dir` and flocks it with `op` (LOCK_EX or LOCK_SH);
/// IoError when it cannot be created or another process holds it (`busy` says what holds it).
int lock_file(const std::string& dir, const std::string& name, int op, const std::string& busy) {
    const std::string p = (std::filesystem::path(dir) / name).string();
    const int fd = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(p + ": cannot create lock file (" + std::strerror(errno) + ")");
    if (::flock(fd, op | LOCK_NB) != 0) {
        ::close(fd);
        throw IoError(dir + ": " + busy + " (" + p + " is locked)");
    }
    return fd;
}
}  // namespace

BatchDirLock::BatchDirLock(const std::string& dir, std::uint32_t shard, std::uint32_t shards) {
    if (shards <= 1) {
        fd_ = lock_file(dir, ".meshless-batch.lock", LOCK_EX, "another meshless batch is writing to this folder");
        return;
    }
    fd_ = lock_file(dir, ".meshless-batch.lock", LOCK_SH, "a meshless batch of the whole archive is writing to this folder");
    const std::string k = std::to_string(shard + 1), n = std::to_string(shards);
    try {
        shard_fd_ = lock_file(dir, ".meshless-batch-shard-" + k + "-of-" + n + ".lock", LOCK_EX,
                              "shard " + k + "/" + n + " is already running into this folder");
    } catch (...) {
        ::close(fd_);
        throw;
    }
}

BatchDirLock::~BatchDirLock() {
    if (shard_fd_ >= 0) ::close(shard_fd_);
    ::close(fd_);
}

}  // namespace meshless
