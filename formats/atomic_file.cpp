#include "formats/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "kernels/errors.hpp"

namespace meshless {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    if (path_ == "-") {
        file_ = stdout;
        return;
    }
    std::error_code ec;
    if (fs::is_directory(path_, ec))
        throw IoError(path_ + ": is a directory, expected a file name");
    tmp_ = path_ + ".tmp-" + std::to_string(::getpid());
    file_ = std::fopen(tmp_.c_str(), "wb+");
    if (!file_) throw IoError(path_ + ": cannot create (" + std::strerror(errno) + ")");
}

AtomicFile::~AtomicFile() {
    if (is_stdout()) return;
    if (file_) std::fclose(file_);
    if (!committed_ && !tmp_.empty()) std::remove(tmp_.c_str());
}

void AtomicFile::write(const void* data, std::size_t n) {
    if (n == 0) return;
    if (std::fwrite(data, 1, n, file_) != n) {
        if (errno == EPIPE) throw BrokenPipe();
        throw IoError(path_ + ": write failed (" + std::strerror(errno) + ")");
    }
}

void AtomicFile::pwrite(std::size_t offset, const void* data, std::size_t n) {
    if (is_stdout()) throw IoError("-: cannot seek on standard output");
    const long here = std::ftell(file_);
    if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 ||
        std::fwrite(data, 1, n, file_) != n || std::fseek(file_, here, SEEK_SET) != 0)
        throw IoError(path_ + ": write failed (" + std::strerror(errno) + ")");
}

void AtomicFile::commit() {
    if (committed_) return;
    if (is_stdout()) {
        if (std::fflush(stdout) != 0) {
            if (errno == EPIPE) throw BrokenPipe();
            throw IoError("-: write failed (" + std::string(std::strerror(errno)) + ")");
        }
        committed_ = true;
        return;
    }
    const bool flush_ok = std::fflush(file_) == 0 && ::fsync(fileno(file_)) == 0;
    const int err = errno;
    std::fclose(file_);
    file_ = nullptr;
    if (!flush_ok) throw IoError(path_ + ": write failed (" + std::strerror(err) + ")");
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
        throw IoError(path_ + ": cannot rename temporary file into place (" + std::strerror(errno) + ")");
    committed_ = true;
}

}  // namespace meshless
