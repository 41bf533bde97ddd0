#include "formats/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "kernels/errors.hpp"

namespace meshless {

namespace fs = std::filesystem;

bool is_streaming_output(const std::string& path) {
    if (path == "-") return true;
    std::error_code ec;
    const auto st = fs::status(path, ec);
    return fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st);
}

std::optional<std::uint64_t> free_space_for_output(const std::string& path) {
    if (is_streaming_output(path)) return std::nullopt;
    std::error_code ec;
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    const fs::space_info si = fs::space(dir, ec);
    if (ec) return std::nullopt;
    return static_cast<std::uint64_t>(si.available);
}

void sync_to_disk(const std::string& path) {
    auto sync_one = [&](const std::string& p, int flags) {
        const int fd = ::open(p.c_str(), flags | O_CLOEXEC);
        if (fd < 0) throw IoError(path + ": cannot open to sync (" + std::strerror(errno) + ")");
        const bool ok = ::fsync(fd) == 0;
        const int err = errno;
        ::close(fd);
        if (!ok) throw IoError(path + ": cannot sync to disk (" + std::strerror(err) + ")");
    };
    sync_one(path, O_RDONLY);
    // the directory the file's name is in (a symbolic link's target, as AtomicFile renames there)
    std::error_code ec;
    const fs::path real = fs::weakly_canonical(path, ec);
    const fs::path dir = (ec ? fs::path(path) : real).parent_path();
    sync_one(dir.empty() ? std::string(".") : dir.string(), O_RDONLY | O_DIRECTORY);
}

AtomicFile::AtomicFile(std::string path, Durability durability) : path_(std::move(path)), durability_(durability) {
    if (path_ == "-") {
        file_ = stdout;
        return;
    }
    // the stdio buffer first: nothing after the file is opened may throw before the object exists
    buffer_.reset(new char[kBufferBytes]);  // (not zeroed: a small file touches a few pages of it)
    std::error_code ec;
    if (fs::is_directory(path_, ec)) throw IoError(path_ + ": is a directory, expected a file name");
    // What the path names, links followed by the kernel (so /dev/stdout, /proc/self/fd/N reach the
    // pipe or file they stand for): a device, FIFO or socket (/dev/null, a named pipe, a pipe) is
    // written directly, never replaced.
    const auto st = fs::status(path_, ec);
    if (fs::exists(st) && !fs::is_regular_file(st)) {
        file_ = std::fopen(path_.c_str(), "wb");
        if (!file_) throw IoError(path_ + ": cannot open for writing (" + std::strerror(errno) + ")");
        direct_ = true;
        buffer_file();
        return;
    }
    // A symbolic link to a file is followed: the temporary goes beside the target, which is replaced.
    std::string target = path_;
    if (fs::is_symlink(path_, ec)) target = fs::weakly_canonical(path_, ec).string();
    if (fs::is_directory(target, ec))
        throw IoError(path_ + ": is a directory, expected a file name");
    target_ = target;
    remove_stale_temporaries(target);
    tmp_ = target + ".tmp-" + std::to_string(::getpid());
    // registered before it exists: a signal between fopen and the registration would leave it
    registration_.reset(tmp_);
    file_ = std::fopen(tmp_.c_str(), "wb+");
    if (!file_) throw IoError(path_ + ": cannot create (" + std::strerror(errno) + ")");
    buffer_file();
}

void AtomicFile::buffer_file() {
    // Large outputs (PLY, VTP, streams, pictures) then reach the kernel in 1 MiB writes: on a
    // 30 MB PLY, 1,456 write calls (most of 4 KiB) become ~35.
    std::setvbuf(file_, buffer_.get(), _IOFBF, kBufferBytes);
}

AtomicFile::~AtomicFile() {
    if (is_stdout()) return;
    if (direct_) {
        if (file_) std::fclose(file_);
        return;
    }
    if (file_) std::fclose(file_);
    if (!committed_ && !tmp_.empty()) std::remove(tmp_.c_str());
    registration_.release();
}

void AtomicFile::write(const void* data, std::size_t n) {
    if (n == 0) return;
    if (std::fwrite(data, 1, n, file_) != n) {
        if (errno == EPIPE) throw BrokenPipe();
        throw IoError(path_ + ": write failed (" + std::strerror(errno) + ")");
    }
    written_ += n;
    constexpr std::size_t kWriteBackStep = std::size_t{8} << 20;
    if (durability_ == Durability::fsync && !tmp_.empty() && written_ - synced_ >= kWriteBackStep && std::fflush(file_) == 0) {
        // start write-back of what is written so far (does not wait for it); a failure here is
        // not an error: commit()'s fsync is what guarantees the data
        ::sync_file_range(fileno(file_), static_cast<off_t>(synced_), static_cast<off_t>(written_ - synced_),
                          SYNC_FILE_RANGE_WRITE);
        synced_ = written_;
    }
}

void AtomicFile::flush() {
    if (std::fflush(file_) != 0) {
        if (errno == EPIPE) throw BrokenPipe();
        throw IoError(path_ + ": write failed (" + std::strerror(errno) + ")");
    }
}

void AtomicFile::pwrite(std::size_t offset, const void* data, std::size_t n) {
    if (is_stdout() || direct_) throw IoError(path_ + ": cannot seek in this output (not a regular file)");
    const long here = std::ftell(file_);
    if (std::fseek(file_, static_cast<long>(offset), SEEK_SET) != 0 ||
        std::fwrite(data, 1, n, file_) != n || std::fseek(file_, here, SEEK_SET) != 0)
        throw IoError(path_ + ": write failed (" + std::strerror(errno) + ")");
}

bool AtomicFile::replace_by_exchange() {
    // An existing regular target is swapped with the temporary in one step (renameat2
    // RENAME_EXCHANGE: readers see the old or the new file, never none) and the old file, now under
    // the temporary's name, is unlinked. A rename over an existing file makes ext4 (auto_da_alloc)
    // write the new file out within the rename: 30-80 ms for a 50 MB output, most of a short run.
    // Not possible (no target yet, another file type, a file system without the flag): false, and
    // commit() renames as usual.
    struct stat st{};
    if (::lstat(target_.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
    if (::renameat2(AT_FDCWD, tmp_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) return false;
    // the old version, now under the temporary's name
    if (::unlink(tmp_.c_str()) == 0) return true;
    // Not removable (what was swapped out is not the file lstat saw, e.g. a directory put there
    // meanwhile): swap back and let commit() rename, which reports such a target as an error.
    const int err = errno;
    if (::renameat2(AT_FDCWD, tmp_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0)
        throw IoError(path_ + ": the previous version, swapped out to " + tmp_ + ", could not be removed (" +
                      std::strerror(err) + ") nor swapped back (" + std::strerror(errno) + ")");
    return false;
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
    if (direct_) {
        const bool ok = std::fflush(file_) == 0;
        const int err = errno;
        std::fclose(file_);
        file_ = nullptr;
        if (!ok) {
            if (err == EPIPE) throw BrokenPipe();
            throw IoError(path_ + ": write failed (" + std::strerror(err) + ")");
        }
        committed_ = true;
        return;
    }
    const bool flush_ok =
        std::fflush(file_) == 0 && (durability_ != Durability::fsync || ::fsync(fileno(file_)) == 0);
    const int err = errno;
    std::fclose(file_);
    file_ = nullptr;
    if (!flush_ok) throw IoError(path_ + ": write failed (" + std::strerror(err) + ")");
    if (durability_ == Durability::replace && replace_by_exchange()) {
        registration_.release();
        committed_ = true;
        return;
    }
    if (std::rename(tmp_.c_str(), target_.c_str()) != 0)
        throw IoError(path_ + ": cannot rename temporary file into place (" + std::strerror(errno) + ")");
    registration_.release();
    committed_ = true;
}

}  // namespace meshless
