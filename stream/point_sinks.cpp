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

PlySink::PlySink(const std::string& path, const std::vector<std::string>& comments, bool with_blocks)
    : path_(path), comments_(comments), blocks_(with_blocks) {
    // stdout, devices and FIFOs cannot seek to patch the count: hold the points, write at the end
    if (!is_streaming_output(path)) w_ = std::make_unique<PlyPointWriter>(path, comments, with_blocks);
}

void PlySink::consume(Batch&& b) {
    require_points(b);
    if (blocks_ && b.point_block.size() != b.points.size())
        throw FormatError("PLY writer: a batch of " + std::to_string(b.points.size()) + " points has " +
                          std::to_string(b.point_block.size()) + " block ids");
    count_ += b.points.size();
    if (w_) {
        if (blocks_) w_->append(b.points, b.point_block);
        else w_->append(b.points);
    } else {
        held_.insert(held_.end(), b.points.begin(), b.points.end());
        if (blocks_) held_blocks_.insert(held_blocks_.end(), b.point_block.begin(), b.point_block.end());
    }
}

void PlySink::finish() {
    if (w_) w_->commit();
    else if (blocks_) write_ply_points(path_, held_, comments_, std::span<const std::uint32_t>(held_blocks_));
    else write_ply_points(path_, held_, comments_);
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
