// The footprint spool: the EWA splat footprints the splat sink computed as the points arrived
// (kernels/splat_rasterizer.hpp EwaFootprint, 60 bytes each, native byte order), kept once and read
// back in parts for both passes, so that they are never recomputed from the points (stream/
// splat_sink.hpp; dissertation section 3.6).
//
// Two tiers: the first footprints stay in memory, in chunks of up to 4 MiB on transparent huge
// pages (stream/large_page_allocator.hpp: a few page faults, no copy through the kernel, read in
// place by visit()), as long as the spool's SpoolMemory budget (which several spools may share)
// grants chunks; the rest go to an unlinked temporary file, created in $TMPDIR (else /tmp) as
// meshless-PURPOSE-XXXXXX when the spool is made and unlinked at once (formats/temporary_files.hpp
// unlinked_temporary), so that an unusable directory fails before the first footprint and the
// file's space is freed however the process ends. Memory: the spools sharing a budget hold at
// most its bytes together, whatever the number of footprints or of spools.
// Errors: IoError naming the spool file (and saying it is a deleted temporary) when it cannot be
// created, written or read back, or when a range past the end is asked for.
// Threads: append/flush from one thread at a time; read() and visit() are thread-safe (pread,
// read-only chunks) once flushed and while nothing is appended.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "kernels/splat_rasterizer.hpp"
#include "stream/large_page_allocator.hpp"

namespace meshless {

/// Bytes of memory chunks that footprint spools may still take (thread-safe).
class SpoolMemory {
public:
    explicit SpoolMemory(std::size_t bytes) : total_(bytes), left_(bytes) {}
    /// The budget it was made with.
    std::size_t total() const { return total_; }
    /// Takes up to `want` bytes, at least `least` (else none); returns the bytes taken.
    std::size_t take(std::size_t want, std::size_t least);
    std::size_t left() const { return left_.load(std::memory_order_relaxed); }

private:
    std::size_t total_;
    std::atomic<std::size_t> left_;
};

class FootprintSpool {
public:
    /// Footprints per memory chunk (4 MiB).
    static constexpr std::size_t kChunk = (std::size_t{4} << 20) / sizeof(EwaFootprint);

    /// Creates and unlinks the file; `purpose` goes into its name. memory: the budget its memory
    /// tier takes chunks from (null or empty: all in the file).
    explicit FootprintSpool(const std::string& purpose = "splat-footprints", std::shared_ptr<SpoolMemory> memory = {});
    ~FootprintSpool();
    FootprintSpool(const FootprintSpool&) = delete;
    FootprintSpool& operator=(const FootprintSpool&) = delete;

    /// Appends footprints (the file's part buffered: call flush() before read()).
    void append(std::span<const EwaFootprint> footprints);
    void flush();
    std::uint64_t size() const { return count_; }
    /// Footprints held in memory (the first ones appended).
    std::uint64_t in_memory() const { return std::min<std::uint64_t>(count_, memory_capacity_); }
    /// Bytes of the memory tier (the chunks' capacity, taken from the budget).
    std::size_t memory_bytes() const { return static_cast<std::size_t>(memory_capacity_) * sizeof(EwaFootprint); }
    /// Reads footprints [first, first + out.size()); they must all have been appended.
    void read(std::uint64_t first, std::span<EwaFootprint> out) const;
    /// Calls fn(std::span<const EwaFootprint>) on footprints [first, first + count) in order, in
    /// pieces: those in memory in place, those in the file read into `scratch` (resized).
    template <class Fn>
    void visit(std::uint64_t first, std::uint64_t count, std::vector<EwaFootprint>& scratch, Fn&& fn) const;
    const std::string& name() const { return name_; }

private:
    [[noreturn]] void fail(const char* what, int err) const;
    void check_range(std::uint64_t first, std::uint64_t count) const;
    /// Reads out.size() footprints of the file part, from its footprint `first`.
    void read_file(std::uint64_t first, std::span<EwaFootprint> out) const;
    std::FILE* f_ = nullptr;
    std::string name_;
    std::uint64_t count_ = 0;
    std::uint64_t memory_capacity_ = 0;  // footprints the chunks hold (all full-size but the last)
    bool sealed_ = false;                // no more chunks: the budget granted less than a full one
    std::shared_ptr<SpoolMemory> memory_;
    std::vector<LargeBuffer<EwaFootprint>> chunks_;
};

template <class Fn>
void FootprintSpool::visit(std::uint64_t first, std::uint64_t count, std::vector<EwaFootprint>& scratch, Fn&& fn) const {
    check_range(first, count);
    const std::uint64_t end = first + count, mem_end = std::min(end, in_memory());
    for (std::uint64_t i = first; i < mem_end;) {
        const LargeBuffer<EwaFootprint>& c = chunks_[static_cast<std::size_t>(i / kChunk)];
        const std::size_t off = static_cast<std::size_t>(i % kChunk);
        const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(mem_end - i, kChunk - off));
        fn(std::span<const EwaFootprint>(c.data() + off, n));
        i += n;
    }
    const std::uint64_t from = std::max(first, mem_end);
    if (end > from) {
        scratch.resize(static_cast<std::size_t>(end - from));
        read_file(from - in_memory(), scratch);
        fn(std::span<const EwaFootprint>(scratch));
    }
}

}  // namespace meshless
