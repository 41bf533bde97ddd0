#include "stream/dedup_sink.hpp"

namespace meshless {

void DedupSink::consume(Batch&& b) {
    if (b.kind == RecordKind::point) {
        const bool blocks = b.point_block.size() == b.points.size() && !b.points.empty();
        std::size_t kept = 0;
        for (std::size_t i = 0; i < b.points.size(); ++i) {
            const PointRecord& p = b.points[i];
            if (!dedup_.keep(Vec3{p.pos[0], p.pos[1], p.pos[2]}, p.radius)) continue;
            if (blocks) b.point_block[kept] = b.point_block[i];
            b.points[kept++] = p;
        }
        b.points.resize(kept);
        if (blocks) b.point_block.resize(kept);
    }
    next_.consume(std::move(b));
}

}  // namespace meshless
