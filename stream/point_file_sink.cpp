#include "stream/point_file_sink.hpp"

#include "kernels/errors.hpp"

namespace meshless {

void VtpSink::observe(const Batch& b) {
    w_.append(b.points, blocks_ ? std::span<const std::uint32_t>(b.point_block) : std::span<const std::uint32_t>{});
}

PointFileSink::PointFileSink(const std::string& path, GeometryFormat format, const std::vector<std::string>& comments,
                             VtpOptions vtp, bool with_blocks, std::optional<ShadingParams> ply_colors) {
    if (format == GeometryFormat::vtp) vtp_.emplace(path, comments, vtp, with_blocks);
    else ply_.emplace(path, comments, with_blocks, ply_colors);
}

void PointFileSink::consume(Batch&& b) {
    if (ply_) ply_->consume(std::move(b));
    else vtp_->observe(b);
}

void PointFileSink::observe(const Batch& b) {
    if (ply_) ply_->observe(b);
    else vtp_->observe(b);
}

void PointFileSink::finish() {
    if (ply_) ply_->finish();
    else vtp_->finish();
}

}  // namespace meshless
