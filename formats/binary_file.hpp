// Whole-file and byte-range reads with one large read, with errors that name the path; and
// FileRangeReader, which keeps one file open for many range reads (a volume read slab by slab).
//
// Units: byte offsets and counts. Throws IoError when the path cannot be opened, is a directory,
// or a read fails; FormatError ("PATH: truncated: need N bytes at offset O, file has M") when the
// requested range extends past the end of the file. Thread-safety: reentrant.
// Dissertation: none (input plumbing for chapter 3).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace meshless {

/// Refuses what is not a regular file before anything opens it (opening a FIFO blocks until a
/// writer comes): IoError "PATH: not a regular file (a FIFO: give - to read a pipe)" for FIFOs,
/// sockets and devices, "PATH: is a directory, expected a file" for directories. A path that does
/// not exist passes (the open that follows names it).
void require_regular_file(const std::string& path);
/// Size of a regular file; IoError if missing or a directory.
std::uint64_t regular_file_size(const std::string& path);
/// The whole file.
std::vector<std::byte> read_file_bytes(const std::string& path);
/// Exactly `count` bytes starting at `offset`.
std::vector<std::byte> read_file_range(const std::string& path, std::uint64_t offset, std::uint64_t count);
/// Reads exactly `count` bytes at `offset` into `dst` (which must hold them).
void read_file_range_into(const std::string& path, std::uint64_t offset, std::uint64_t count, std::byte* dst);
/// A regular file opened once for any number of range reads (pread(2): no shared file position, so
/// read_into may run on several threads at once). Its size is taken at open, so a range past it
/// is the truncation FormatError above; a file that shrinks later gives the IoError of a short read.
class FileRangeReader {
public:
    /// IoError when the path cannot be opened or is not a regular file (a directory, a FIFO).
    explicit FileRangeReader(const std::string& path);
    ~FileRangeReader();
    FileRangeReader(const FileRangeReader&) = delete;
    FileRangeReader& operator=(const FileRangeReader&) = delete;
    std::uint64_t size() const { return size_; }
    const std::string& path() const { return path_; }
    /// Reads exactly `count` bytes at `offset` into `dst` (which must hold them).
    void read_into(std::uint64_t offset, std::uint64_t count, std::byte* dst) const;

private:
    std::string path_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
};

/// Whether `path` is a regular file whose first bytes are `magic` (false for FIFOs, which are not
/// opened, for files that cannot be opened and for shorter files; never throws): how the store
/// readers recognise their files.
bool file_starts_with(const std::string& path, std::string_view magic) noexcept;

/// Up to `max_bytes` from the start of the file (fewer if the file is shorter), as text.
std::string read_file_prefix(const std::string& path, std::size_t max_bytes);

}  // namespace meshless
