// The point spool: oriented points written once to an unlinked temporary file and read back as
// often as needed, so that a consumer that needs the points more than once (the EWA splat kernel's
// second pass, a turntable's frames, a picture whose frame must be known before its first point)
// holds one batch in memory, not all of them.
//
// The file is created in $TMPDIR (else /tmp) as meshless-PURPOSE-XXXXXX and unlinked at once, so
// its space is freed however the process ends; it holds raw PointRecords (32 bytes each, native
// byte order), in the order appended. The spool tracks the bounds of the finite positions
// (kernels/splat_rasterizer.hpp PointBounds) and the range of the finite values, known once every
// point is in. Points that come with block ids (Batch::point_block, the multiblock path) keep them:
// a second unlinked file (meshless-PURPOSE-blocks-XXXXXX) holds one uint32 per point, and the
// source replays them into Batch::point_block. Either every point has an id or none does (a
// batch with points and without ids after one with them, or the reverse, is a FormatError).
//
// In place: a PLY file whose vertices are stored exactly as PointRecords (formats/ply_points.hpp
// PlyPointReader::records_offset(), what `isosurface` and `write` make) is its own spool: it is read
// once on construction (bounds, value range, and the reader's checks: truncated body, trailing
// bytes) and replayed from the file; nothing is written (a copy of 10^7 points is 305 MB).
//
// PointSpool is a Sink (requires point batches: FormatError on samples), so a graph can end in it;
// finish() flushes. PointSpoolSource replays it in batches of at most kMaxBatchRecords, with dense
// sequence numbers, reading each batch into a recycled array: the source holds at most one batch.
// Errors: IoError naming the spool file (and saying it is a deleted temporary, or the input read in
// place) when it cannot be created, written or read back.
// Threads: append/consume/finish from one thread at a time; read() is thread-safe (pread) once the
// spool is flushed and while nothing is appended.
#pragma once
#include <array>
#include <cstdio>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "kernels/splat_rasterizer.hpp"
#include "stream/stage.hpp"

namespace meshless {

class PlyPointReader;

class PointSpool final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    /// Creates and unlinks the file; `purpose` goes into its name (e.g. "splat-spool").
    explicit PointSpool(const std::string& purpose = "point-spool");
    /// Whether the PLY file at path can be a spool in place (see above); false for anything else,
    /// a file that cannot be opened or parsed included (its reader then reports why).
    static bool can_be_in_place(const std::string& ply_path);
    struct InPlace {};
    /// The PLY file as its own spool, read on `threads` threads (the bounds and value range do not
    /// depend on the count). Throws FormatError/IoError naming it (FormatError also when it is not
    /// such a file: can_be_in_place). append() and observe() are refused (std::logic_error).
    PointSpool(InPlace, const std::string& ply_path, int threads = 1);
    ~PointSpool() override;
    PointSpool(const PointSpool&) = delete;
    PointSpool& operator=(const PointSpool&) = delete;

    /// Appends points (buffered: call flush() before read()); blocks: empty or one id per point.
    void append(std::span<const PointRecord> points, std::span<const std::uint32_t> blocks = {});
    void consume(Batch&& b) override { observe(b); }
    void observe(const Batch& b) override;
    void finish() override { flush(); }
    void flush();

    std::uint64_t size() const { return count_; }
    /// point_bounds() of every point appended (in place: of the file's points).
    std::array<Vec3, 2> bounds() const { return tally_.bounds.bounds(); }
    /// {min, max} of the finite values appended; nullopt when there is none.
    std::optional<std::array<double, 2>> value_range() const;
    /// How many of the points appended (in place: of the file's points) cannot be drawn
    /// (kernels/records.hpp drawable); splat spools a PLY with any through a filter instead.
    std::uint64_t undrawable() const { return tally_.undrawable; }
    /// True when the points came with block ids.
    bool has_blocks() const { return blocks_ != nullptr; }
    /// 1 + the largest block id appended (0 without ids).
    std::uint32_t block_count() const { return block_count_; }
    /// Reads the block ids of points [first, first + out.size()); has_blocks() must be true.
    void read_blocks(std::uint64_t first, std::span<std::uint32_t> out) const;
    /// Reads points [first, first + out.size()) into out; they must all have been appended.
    void read(std::uint64_t first, std::span<PointRecord> out) const;
    /// The file's name as created (it no longer exists in the directory); in place: the PLY's path.
    const std::string& name() const { return name_; }

private:
    [[noreturn]] void fail(const char* what, int err) const;
    static std::FILE* create(const std::string& purpose, std::string& name);
    static void pread_all(std::FILE* f, const std::string& name, char* dst, std::size_t bytes, std::uint64_t offset,
                          const char* kind);
    const char* kind() const { return in_place_ ? "the input, read in place" : "deleted temporary file"; }
    std::FILE* f_ = nullptr;
    std::FILE* blocks_ = nullptr;
    std::string purpose_, blocks_name_;
    std::uint32_t block_count_ = 0;
    std::string name_;
    std::uint64_t count_ = 0;
    std::uint64_t base_ = 0;     // byte offset of point 0 in f_
    bool in_place_ = false;      // f_ is the input PLY file
    // The running summary of the points: bounds, finite value range.
    struct Tally {
        PointBounds bounds;
        double lo = 0, hi = 0;
        bool any = false;
        std::uint64_t undrawable = 0;
        void add(std::span<const PointRecord> points);
        void merge(const Tally& o);
    };
    Tally tally_;
    void scan_in_place(PlyPointReader& r, int threads);  // count, tally of the in-place file f_
};

class PointSpoolSource final : public Source {
public:
    Payload gives() const override { return Payload::points; }
    /// Flushes the spool; the spool must outlive the source and not grow while it is read.
    explicit PointSpoolSource(PointSpool& spool, std::size_t batch_records = kMaxBatchRecords);
    std::optional<Batch> next() override;
    /// Keeps one consumed array to read the next batch into.
    bool recycle(Batch& consumed) override;
    /// Bytes of record arrays the source holds now (at most one batch), for tests.
    std::size_t retained_bytes();

private:
    const PointSpool& spool_;
    std::size_t per_;
    std::uint64_t at_ = 0;
    std::uint64_t seq_ = 0;
    std::mutex m_;  // recycle() may run on the sink's thread while next() runs
    std::vector<PointRecord> spare_;
    std::vector<std::uint32_t> spare_blocks_;
};

}  // namespace meshless
