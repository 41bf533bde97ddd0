#include "stream/block_cell_source.hpp"

#include <algorithm>

#include "kernels/barycentric_lattice.hpp"
#include "kernels/marching_cubes_table.hpp"

namespace meshless {

std::int64_t block_seed_unit_cells(int n) {
    const auto per_cell = static_cast<std::int64_t>(kMcMaxTriangles) * static_cast<std::int64_t>(lattice_size(std::max(1, n)));
    return std::clamp<std::int64_t>(static_cast<std::int64_t>(kMaxBatchRecords) / per_cell, 1, 256);
}

BlockCellSource::BlockCellSource(std::vector<std::int64_t> first_cell, std::int64_t cells_per_unit)
    : first_(std::move(first_cell)), per_(std::max<std::int64_t>(1, cells_per_unit)) {
    if (!first_.empty()) at_ = first_[0];
}

std::optional<Batch> BlockCellSource::next() {
    // skip blocks without (remaining) cells
    while (block_ + 1 < first_.size() && at_ >= first_[block_ + 1]) {
        ++block_;
        at_ = first_[block_];
    }
    if (block_ + 1 >= first_.size()) return std::nullopt;
    Batch b;
    b.seq = seq_++;
    b.kind = RecordKind::seed;
    b.cells.k0 = at_;
    b.cells.k1 = std::min(first_[block_ + 1], at_ + per_);
    at_ = b.cells.k1;
    return b;
}

}  // namespace meshless
