// A Source over a PLY point set (formats/ply_points.hpp PlyPointReader): batches of at most
// kMaxBatchRecords points read as they are pulled, so `meshless splat FILE.ply` holds one batch,
// not the file. Throws FormatError/IoError naming the file (truncated body, trailing bytes).
// With drop_undrawable, points that cannot be drawn (kernels/records.hpp drawable: a NaN/Inf
// position, normal, radius or value, a zero normal or radius) are left out and counted (dropped()).
// Not thread-safe (the runner calls next() serially).
#pragma once
#include <optional>
#include <string>

#include "formats/ply_points.hpp"
#include "stream/stage.hpp"

namespace meshless {

class PlySource final : public Source {
public:
    Payload gives() const override { return Payload::points; }
    explicit PlySource(const std::string& path, bool drop_undrawable = false) : r_(path), drop_(drop_undrawable) {}
    const std::vector<std::string>& comments() const { return r_.comments(); }
    std::uint64_t count() const { return r_.count(); }
    /// Points left out so far (drop_undrawable).
    std::uint64_t dropped() const { return dropped_; }
    std::optional<Batch> next() override {
        Batch b;
        b.kind = RecordKind::point;
        for (;;) {
            if (r_.read(b.points, kMaxBatchRecords, &b.point_block) == 0) return std::nullopt;
            if (drop_) drop_undrawable(b);
            if (!b.points.empty()) break;  // a batch of nothing but dropped points: read on
        }
        b.seq = seq_++;
        return b;
    }

private:
    void drop_undrawable(Batch& b) {
        const bool blocks = b.point_block.size() == b.points.size();
        std::size_t kept = 0;
        for (std::size_t i = 0; i < b.points.size(); ++i) {
            if (!drawable(b.points[i])) continue;
            b.points[kept] = b.points[i];
            if (blocks) b.point_block[kept] = b.point_block[i];
            ++kept;
        }
        dropped_ += b.points.size() - kept;
        b.points.resize(kept);
        if (blocks) b.point_block.resize(kept);
    }
    PlyPointReader r_;
    bool drop_ = false;
    std::uint64_t seq_ = 0;
    std::uint64_t dropped_ = 0;
};

}  // namespace meshless
