// A Source over a PLY point set (formats/ply_points.hpp PlyPointReader): batches of at most
// kMaxBatchRecords points read as they are pulled, so `meshless splat FILE.ply` holds one batch,
// not the file. Throws FormatError/IoError naming the file (truncated body, trailing bytes).
// Not thread-safe (the runner calls next() serially).
#pragma once
#include <optional>
#include <string>

#include "formats/ply_points.hpp"
#include "stream/stage.hpp"

namespace meshless {

class PlySource final : public Source {
public:
    explicit PlySource(const std::string& path) : r_(path) {}
    const std::vector<std::string>& comments() const { return r_.comments(); }
    std::uint64_t count() const { return r_.count(); }
    std::optional<Batch> next() override {
        Batch b;
        b.kind = RecordKind::point;
        if (r_.read(b.points, kMaxBatchRecords, &b.point_block) == 0) return std::nullopt;
        b.seq = seq_++;
        return b;
    }

private:
    PlyPointReader r_;
    std::uint64_t seq_ = 0;
};

}  // namespace meshless
