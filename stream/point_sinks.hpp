// Sinks that end a point pipeline: PlySink streams points into a binary PLY (formats/ply_points.hpp,
// temporary name + rename on finish; to stdout, a FIFO or a device, which cannot seek back to the
// count, the points wait in an unlinked stream/point_spool.hpp file and the PLY is written on finish
// with its count declared: memory one batch, the same bytes), CollectSink keeps them in memory (for tests and benchmarks;
// pictures stream through stream/splat_sink.hpp, turntables replay a stream/point_spool.hpp). Both require point batches (throw FormatError on samples). Not thread-safe.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "formats/ply_points.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "stream/point_spool.hpp"
#include "stream/stage.hpp"

namespace meshless {

class PlySink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    /// with_blocks: the PLY gets the `block` property from Batch::point_block (multiblock points; a
    /// batch without block ids is then a FormatError).
    /// colors: the PLY gets `red green blue`, each point's base colour under these settings
    /// (kernels/splat_rasterizer.hpp splat_base_color: by value, block or normal; unlit).
    PlySink(const std::string& path, const std::vector<std::string>& comments, bool with_blocks = false,
            std::optional<ShadingParams> colors = std::nullopt);
    void consume(Batch&& b) override;
    void finish() override;
    std::uint64_t count() const { return count_; }

private:
    void colors_of(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks);  // into rgb_
    std::string path_;
    std::vector<std::string> comments_;
    std::unique_ptr<PlyPointWriter> w_;   // file output
    std::unique_ptr<PointSpool> spool_;   // stdout, FIFO, device: the count goes up front, so the
                                          // points wait in an unlinked file (memory: one batch)
    std::vector<std::uint8_t> rgb_;
    bool blocks_ = false;
    std::optional<ShadingParams> colors_;
    std::uint64_t count_ = 0;
};

class CollectSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    /// keep_chunks = false: `points` holds everything, in order (one flat array).
    /// keep_chunks = true: each batch's array is kept as it came in `chunks` (no copying; for
    /// consumers that iterate, such as the benchmarks); `points` stays empty.
    explicit CollectSink(bool keep_chunks = false) : keep_chunks_(keep_chunks) {}
    void consume(Batch&& b) override;
    std::size_t size() const { return size_; }
    std::vector<PointRecord> points;
    /// Without keep_chunks: the batches' point_block, in order (empty when they carry none).
    std::vector<std::uint32_t> blocks;
    std::vector<std::vector<PointRecord>> chunks;

private:
    bool keep_chunks_;
    std::size_t size_ = 0;
};

}  // namespace meshless
