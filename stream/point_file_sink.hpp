// The sinks that write a point pipeline's points to a file in a chosen geometry format
// (formats/geometry_format.hpp): VtpSink streams them into VTK XML PolyData
// (formats/vtp_writer.hpp, bounded memory, temporary name + rename on finish), with the per-point
// block ids (Batch::point_block) as a `block` array when the sink is built with_blocks; PointFileSink
// is the one sink the commands build for `-o FILE` (PlySink for PLY, stream/point_sinks.hpp;
// VtpSink for VTP). Both require point batches (FormatError on samples). Not thread-safe (the
// runner calls sinks serially).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "formats/geometry_format.hpp"
#include "formats/vtp_writer.hpp"
#include "stream/point_sinks.hpp"
#include "stream/stage.hpp"

namespace meshless {

class VtpSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    /// with_blocks: the batches' block ids become the `block` array (the multiblock path); without
    /// it they are not written, as in the PLY and the point stream of the same points.
    VtpSink(const std::string& path, const std::vector<std::string>& comments, VtpOptions options = {},
            bool with_blocks = true)
        : w_(path, comments, options), blocks_(with_blocks) {}
    void consume(Batch&& b) override { observe(b); }
    void observe(const Batch& b) override;
    void finish() override { w_.commit(); }
    std::uint64_t count() const { return w_.count(); }

private:
    VtpPointWriter w_;
    bool blocks_;
};

class PointFileSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    /// vtp: the VTP writer's settings (compression, compressing threads), unused for PLY.
    /// with_blocks: the PLY declares the `block` property and the VTP writes the `block` array
    /// (the multiblock path, a stream with block ids); without it neither carries block ids.
    /// ply_colors: PLY output gets `red green blue` (PlySink); VTP ignores it (ParaView colours by
    /// the arrays it has).
    PointFileSink(const std::string& path, GeometryFormat format, const std::vector<std::string>& comments,
                  VtpOptions vtp = {}, bool with_blocks = false, std::optional<ShadingParams> ply_colors = std::nullopt);
    void consume(Batch&& b) override;
    void observe(const Batch& b) override;
    void finish() override;
    /// Points consumed so far.
    std::uint64_t count() const { return ply_ ? ply_->count() : vtp_->count(); }

private:
    std::optional<PlySink> ply_;
    std::optional<VtpSink> vtp_;
};

}  // namespace meshless
