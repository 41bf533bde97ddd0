// The footprint spool: the EWA splat footprints the splat sink computed as the points arrived
// (kernels/splat_rasterizer.hpp EwaFootprint, 60 bytes each, native byte order), written once to an
// unlinked temporary file and read back in parts for both passes, so that they are neither kept in
// memory nor recomputed from the points (stream/splat_sink.hpp; dissertation section 3.6).
//
// The file is created in $TMPDIR (else /tmp) as meshless-PURPOSE-XXXXXX and unlinked at once
// (formats/temporary_files.hpp unlinked_temporary), so its space is freed however the process ends.
// Errors: IoError naming the spool file (and saying it is a deleted temporary) when it cannot be
// created, written or read back.
// Threads: append/flush from one thread at a time; read() is thread-safe (pread) once flushed and
// while nothing is appended.
#pragma once
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

#include "kernels/splat_rasterizer.hpp"

namespace meshless {

class FootprintSpool {
public:
    /// Creates and unlinks the file; `purpose` goes into its name.
    explicit FootprintSpool(const std::string& purpose = "splat-footprints");
    ~FootprintSpool();
    FootprintSpool(const FootprintSpool&) = delete;
    FootprintSpool& operator=(const FootprintSpool&) = delete;

    /// Appends footprints (buffered: call flush() before read()).
    void append(std::span<const EwaFootprint> footprints);
    void flush();
    std::uint64_t size() const { return count_; }
    /// Reads footprints [first, first + out.size()); they must all have been appended.
    void read(std::uint64_t first, std::span<EwaFootprint> out) const;
    const std::string& name() const { return name_; }

private:
    [[noreturn]] void fail(const char* what, int err) const;
    std::FILE* f_ = nullptr;
    std::string name_;
    std::uint64_t count_ = 0;
};

}  // namespace meshless
