#include "stream/point_sinks.hpp"

#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {
void require_points(const Batch& b) {
    if (b.kind != RecordKind::point)
        throw FormatError("point writer: input holds unprojected samples; run 'meshless project' first");
}
}  // namespace

PlySink::PlySink(const std::string& path, const std::vector<std::string>& comments, bool with_blocks,
                 std::optional<ShadingParams> colors)
    : path_(path), comments_(comments), blocks_(with_blocks), colors_(colors) {
    // stdout, devices and FIFOs cannot seek to patch the count: hold the points, write at the end
    if (!is_streaming_output(path)) w_ = std::make_unique<PlyPointWriter>(path, comments, with_blocks, colors.has_value());
}

void PlySink::consume(Batch&& b) {
    require_points(b);
    if (blocks_ && b.point_block.size() != b.points.size())
        throw FormatError("PLY writer: a batch of " + std::to_string(b.points.size()) + " points has " +
                          std::to_string(b.point_block.size()) + " block ids");
    count_ += b.points.size();
    rgb_.clear();
    if (colors_) {
        rgb_.resize(3 * b.points.size());
        for (std::size_t i = 0; i < b.points.size(); ++i) {
            const std::uint32_t c = splat_base_color(*colors_, b.points[i], b.point_block, i);
            rgb_[3 * i] = static_cast<std::uint8_t>(c >> 16);
            rgb_[3 * i + 1] = static_cast<std::uint8_t>(c >> 8);
            rgb_[3 * i + 2] = static_cast<std::uint8_t>(c);
        }
    }
    if (w_) {
        w_->append(b.points, blocks_ ? std::span<const std::uint32_t>(b.point_block) : std::span<const std::uint32_t>{}, rgb_);
    } else {
        held_.insert(held_.end(), b.points.begin(), b.points.end());
        if (blocks_) held_blocks_.insert(held_blocks_.end(), b.point_block.begin(), b.point_block.end());
        held_rgb_.insert(held_rgb_.end(), rgb_.begin(), rgb_.end());
    }
}

void PlySink::finish() {
    if (w_) {
        w_->commit();
        return;
    }
    std::optional<std::span<const std::uint32_t>> blocks;
    if (blocks_) blocks = std::span<const std::uint32_t>(held_blocks_);
    std::optional<std::span<const std::uint8_t>> rgb;
    if (colors_) rgb = std::span<const std::uint8_t>(held_rgb_);
    write_ply_points(path_, held_, comments_, blocks, rgb);
}

void CollectSink::consume(Batch&& b) {
    require_points(b);
    size_ += b.points.size();
    if (keep_chunks_) {
        if (!b.points.empty()) chunks.push_back(std::move(b.points));
    } else if (points.empty()) {
        points = std::move(b.points);
    } else {
        points.insert(points.end(), b.points.begin(), b.points.end());
    }
}

}  // namespace meshless
