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

PlySink::PlySink(const std::string& path, const std::vector<std::string>& comments)
    : path_(path), comments_(comments) {
    // stdout, devices and FIFOs cannot seek to patch the count: hold the points, write at the end
    if (!is_streaming_output(path)) w_ = std::make_unique<PlyPointWriter>(path, comments);
}

void PlySink::consume(Batch&& b) {
    require_points(b);
    count_ += b.points.size();
    if (w_) w_->append(b.points);
    else held_.insert(held_.end(), b.points.begin(), b.points.end());
}

void PlySink::finish() {
    if (w_) w_->commit();
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
