// The footprint spool: the EWA splat footprints pass 1 computed (kernels/splat_rasterizer.hpp
// EwaFootprint, 60 bytes each, native byte order), written once to an unlinked temporary file and
// read back in parts (copied, or mapped without a copy) for the two EWA passes, so that they are
// neither kept in memory nor recomputed
// from the points (stream/splat_sink.hpp; dissertation section 3.6).
//
// The file is created in $TMPDIR (else /tmp) as meshless-PURPOSE-XXXXXX and unlinked at once
// (formats/temporary_files.hpp unlinked_temporary), so its space is freed however the process ends.
// Errors: IoError naming the spool file (and saying it is a deleted temporary) when it cannot be
// created, written or read back.
// Threads: append/flush from one thread at a time; read() and view() are thread-safe (pread, mmap)
// once flushed and while nothing is appended.
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

    /// Footprints [first, first + count) mapped read-only from the spool (no copy), unmapped when
    /// the view goes. Memory: the pages of the range, while the view lives. Same errors as read().
    class View {
    public:
        View(const View&) = delete;
        View& operator=(const View&) = delete;
        ~View();
        std::span<const EwaFootprint> footprints() const { return fps_; }

    private:
        friend class FootprintSpool;
        View(void* base, std::size_t bytes, std::span<const EwaFootprint> fps) : base_(base), bytes_(bytes), fps_(fps) {}
        void* base_;
        std::size_t bytes_;
        std::span<const EwaFootprint> fps_;
    };
    /// Precondition: flush() since the last append.
    View view(std::uint64_t first, std::uint64_t count) const;
    const std::string& name() const { return name_; }

private:
    [[noreturn]] void fail(const char* what, int err) const;
    void check_range(std::uint64_t first, std::uint64_t count) const;
    std::FILE* f_ = nullptr;
    std::string name_;
    std::uint64_t count_ = 0;
};

}  // namespace meshless
