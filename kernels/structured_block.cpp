#include "kernels/structured_block.hpp"

namespace meshless {

PointSet to_point_set(const Multiblock& mb) {
    PointSet ps;
    ps.value_name = mb.value_name;
    ps.dropped_blanked = mb.blanked;
    ps.dropped_nonfinite = mb.nonfinite;
    std::size_t total = 0;
    for (const auto& b : mb.blocks) total += b.node.size();
    ps.pos.reserve(total);
    ps.value.reserve(total);
    for (const auto& b : mb.blocks) {
        PointSetBlock pb;
        pb.name = b.name;
        pb.dims = b.dims;
        pb.first = ps.pos.size();
        for (std::int64_t n = 0; n < b.node_count(); ++n) {
            if (!b.is_valid(n) || b.is_covered(n)) continue;
            ps.pos.push_back(b.node[static_cast<std::size_t>(n)]);
            ps.value.push_back(b.value[static_cast<std::size_t>(n)]);
        }
        pb.count = ps.pos.size() - pb.first;
        ps.blocks.push_back(std::move(pb));
    }
    return ps;
}

}  // namespace meshless
