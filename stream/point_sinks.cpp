#include "stream/point_sinks.hpp"

#include <algorithm>

#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

PlySink::PlySink(const std::string& path, const std::vector<std::string>& comments, bool with_blocks,
                 std::optional<ShadingParams> colors)
    : path_(path), comments_(comments), blocks_(with_blocks), colors_(colors) {
    // stdout, devices and FIFOs cannot seek to patch the count: the points wait on disk, the PLY
    // is written at the end with its count declared
    if (!is_streaming_output(path)) w_ = std::make_unique<PlyPointWriter>(path, comments, with_blocks, colors.has_value());
    else spool_ = std::make_unique<PointSpool>("ply-output");
}

void PlySink::colors_of(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks) {
    rgb_.clear();
    if (!colors_) return;
    rgb_.resize(3 * pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const std::uint32_t c = splat_base_color(*colors_, pts[i], blocks, i);
        rgb_[3 * i] = static_cast<std::uint8_t>(c >> 16);
        rgb_[3 * i + 1] = static_cast<std::uint8_t>(c >> 8);
        rgb_[3 * i + 2] = static_cast<std::uint8_t>(c);
    }
}

void PlySink::consume(Batch&& b) {
    if (blocks_ && b.point_block.size() != b.points.size())
        throw FormatError("PLY writer: a batch of " + std::to_string(b.points.size()) + " points has " +
                          std::to_string(b.point_block.size()) + " block ids");
    count_ += b.points.size();
    const std::span<const std::uint32_t> blocks = blocks_ ? std::span<const std::uint32_t>(b.point_block) : std::span<const std::uint32_t>{};
    if (w_) {
        colors_of(b.points, b.point_block);
        w_->append(b.points, blocks, rgb_);
    } else {
        // the block ids wait too when the batches have them (the colours may come from them)
        spool_->append(b.points, b.point_block.size() == b.points.size() ? std::span<const std::uint32_t>(b.point_block)
                                                                          : std::span<const std::uint32_t>{});
    }
}

void PlySink::finish() {
    if (w_) {
        w_->commit();
        return;
    }
    spool_->flush();
    PlyPointWriter w(path_, comments_, blocks_, colors_.has_value(), count_);
    constexpr std::uint64_t kPiece = 1u << 16;
    std::vector<PointRecord> pts;
    std::vector<std::uint32_t> blocks;
    for (std::uint64_t first = 0; first < count_; first += kPiece) {
        const std::size_t n = static_cast<std::size_t>(std::min(kPiece, count_ - first));
        pts.resize(n);
        spool_->read(first, pts);
        blocks.resize(spool_->has_blocks() ? n : 0);
        if (spool_->has_blocks()) spool_->read_blocks(first, blocks);
        colors_of(pts, blocks);
        w.append(pts, blocks_ ? std::span<const std::uint32_t>(blocks) : std::span<const std::uint32_t>{}, rgb_);
    }
    w.commit();
}

void CollectSink::consume(Batch&& b) {
    size_ += b.points.size();
    if (keep_chunks_) {
        if (!b.points.empty()) chunks.push_back(std::move(b.points));
        return;
    }
    blocks.insert(blocks.end(), b.point_block.begin(), b.point_block.end());
    if (points.empty()) points = std::move(b.points);
    else points.insert(points.end(), b.points.begin(), b.points.end());
}

}  // namespace meshless
