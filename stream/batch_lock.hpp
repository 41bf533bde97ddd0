// The lock that keeps two batch jobs (stream/batch_job.hpp) from writing the same outputs.
//
// flock(2) on OUT_DIR/.meshless-batch.lock, held by the object and released when it is destroyed or
// the process ends, however it ends (a kill leaves no stale lock); the lock files themselves stay.
// A whole-archive run takes it exclusively. The shards of a job array (`--shard K/N`) share it, so
// they run side by side but never beside a whole-archive run, and each takes its own
// OUT_DIR/.meshless-batch-shard-K-of-N.lock exclusively, so a shard does not run twice at once.
// Throws IoError naming the file when it cannot be created, and naming the folder when another
// process holds a lock this run needs (no waiting). Not copyable; one object per run.
#pragma once
#include <cstdint>
#include <string>

namespace meshless {

class BatchDirLock {
public:
    /// shard, shards: as BatchSettings (shards = 1: the whole archive).
    explicit BatchDirLock(const std::string& dir, std::uint32_t shard = 0, std::uint32_t shards = 1);
    ~BatchDirLock();
    BatchDirLock(const BatchDirLock&) = delete;
    BatchDirLock& operator=(const BatchDirLock&) = delete;

private:
    int fd_ = -1, shard_fd_ = -1;
};

}  // namespace meshless
