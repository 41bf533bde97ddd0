#include "stream/block_seed_stage.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>

#include "kernels/barycentric_lattice.hpp"
#include "kernels/errors.hpp"

namespace meshless {

BlockSeedStage::BlockSeedStage(const Multiblock& mb, const BlockSeedPlan& plan, double iso, int n)
    : mb_(mb), plan_(plan), iso_(iso), n_(n), lattice_(barycentric_lattice(n)) {
    if (plan.first_cell.size() != mb.blocks.size() + 1 || plan.orientation.size() != mb.blocks.size())
        throw InvalidArgument("block seed stage: the plan was made for another multiblock");
}

void BlockSeedStage::process(Batch& b) const {
    const auto t0 = std::chrono::steady_clock::now();
    assert(b.kind == RecordKind::seed);
    b.seeds.clear();
    BlockSeedStats st;
    if (b.cells.k1 > b.cells.k0) {
        const auto& first = plan_.first_cell;
        // the block whose cells hold k0: the last block starting at or before it
        const auto it = std::upper_bound(first.begin(), first.end() - 1, b.cells.k0);
        const std::size_t block = static_cast<std::size_t>(it - first.begin()) - 1;
        assert(block < mb_.blocks.size() && b.cells.k1 <= first[block + 1]);
        block_cell_seeds(mb_.blocks[block], static_cast<std::uint32_t>(block), plan_.orientation[block],
                         b.cells.k0 - first[block], b.cells.k1 - first[block], iso_, n_, lattice_, b.seeds, st);
    }
    const std::int64_t v[8] = {st.cells, st.invalid_cells, st.degenerate_cells, st.active_cells, st.triangles,
                               st.zero_area_triangles, st.seeds, st.covered_cells};
    for (std::size_t i = 0; i < 8; ++i) st_[i].fetch_add(v[i], std::memory_order_relaxed);
    busy_ns_ += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
}

BlockSeedStats BlockSeedStage::stats() const {
    BlockSeedStats s;
    s.cells = st_[0].load();
    s.invalid_cells = st_[1].load();
    s.degenerate_cells = st_[2].load();
    s.active_cells = st_[3].load();
    s.triangles = st_[4].load();
    s.zero_area_triangles = st_[5].load();
    s.seeds = st_[6].load();
    s.covered_cells = st_[7].load();
    return s;
}

}  // namespace meshless
