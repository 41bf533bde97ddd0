// The lock that keeps two batch jobs (stream/batch_job.hpp) from writing to one output folder.
//
// An exclusive flock(2) on OUT_DIR/.meshless-batch.lock, held by the object and released when it
// is destroyed or the process ends, however it ends (a kill leaves no stale lock); the lock file
// itself stays. Throws IoError naming the file when it cannot be created, and naming the folder
// when another process holds the lock (no waiting). Not copyable; one object per run.
#pragma once
#include <string>

namespace meshless {

class BatchDirLock {
public:
    explicit BatchDirLock(const std::string& dir);
    ~BatchDirLock();
    BatchDirLock(const BatchDirLock&) = delete;
    BatchDirLock& operator=(const BatchDirLock&) = delete;

private:
    int fd_ = -1;
};

}  // namespace meshless
