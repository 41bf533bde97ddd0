// A temporary spool file beside an output: "<out>.tmp-<pid>.spool", created empty, registered for
// removal by the signal handlers (formats/temporary_files.hpp) and removed by the destructor. Bytes
// are appended and read back at their offsets (pread/pwrite: no shared file position). The
// external sorts and converters (ooc/point_store_writer, ooc/brick_converter) keep what does not
// fit their memory budget here.
// Units: bytes. Throws IoError naming the output and the spool ("OUT: cannot create temporary file
// PATH (WHY)", "OUT: write failed (temporary file PATH: WHY)", "OUT: cannot read back temporary file
// PATH"). Thread-safety: read() may run on several threads at once; append() is not reentrant.
// Dissertation: none (out-of-core plumbing).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "formats/temporary_files.hpp"

namespace meshless {

class SpoolFile {
public:
    explicit SpoolFile(const std::string& out);
    ~SpoolFile();
    SpoolFile(const SpoolFile&) = delete;
    SpoolFile& operator=(const SpoolFile&) = delete;
    /// Appends `bytes` bytes; returns the offset of the first.
    std::uint64_t append(const void* p, std::size_t bytes);
    /// Reads exactly `bytes` bytes at `offset` (which append returned, or inside what it wrote).
    void read(std::uint64_t offset, std::size_t bytes, void* dst) const;
    std::uint64_t size() const { return size_; }

private:
    std::string out_, path_;
    TemporaryRegistration registration_;  ///< path_, for the signal handlers
    int fd_ = -1;
    std::uint64_t size_ = 0;
};

}  // namespace meshless
