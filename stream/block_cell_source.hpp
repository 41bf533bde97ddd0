// Source of the multiblock/AMR seed work (dissertation section 4.4): batches that name a range of
// cells of one block, as global cell indices [cells.k0, cells.k1) over the blocks' cells laid end
// to end (block b's cells are [plan.first_cell[b], plan.first_cell[b+1]), kernels/block_cell_seeds.hpp).
// A range never spans two blocks and holds at most `cells_per_unit` cells, chosen so that the seeds
// of a batch never exceed kMaxBatchRecords (block_seed_unit_cells). Sequence numbers are dense
// (0, 1, 2, ...), the order is block by block, cell by cell, and the ranges depend only on the
// blocks and n, never on the thread count. Not thread-safe (the runner calls next() serially).
#pragma once
#include <cstdint>
#include <vector>

#include "stream/stage.hpp"

namespace meshless {

/// Cells per work unit for lattice parameter n: kMaxBatchRecords / (kMcMaxTriangles x n(n+1)/2 seeds),
/// at most 256 and at least 1. 256: the isosurface crosses few cells, unevenly, so units are kept
/// small for the threads to share the Newton work evenly (the three combustor pieces, 1,760 cells,
/// make a few units per piece rather than one each); a unit costs one batch, a few Field::evaluate calls.
std::int64_t block_seed_unit_cells(int n);

class BlockCellSource final : public Source {
public:
    Payload gives() const override { return Payload::cells; }
    /// first_cell: per block its first global cell index, size blocks + 1 (BlockSeedPlan::first_cell).
    BlockCellSource(std::vector<std::int64_t> first_cell, std::int64_t cells_per_unit);
    std::optional<Batch> next() override;
    /// Work units handed out so far.
    std::uint64_t emitted() const { return seq_; }

private:
    std::vector<std::int64_t> first_;
    std::int64_t per_;
    std::size_t block_ = 0;
    std::int64_t at_ = 0;
    std::uint64_t seq_ = 0;
};

}  // namespace meshless
