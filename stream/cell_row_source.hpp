// Source of paradigm (C) work units over a regular grid: batches that name a range of cell rows
// (see kernels/cell_sampling.hpp), each at most kMaxBatchRecords cells, so a batch never exceeds
// the record cap whatever the isovalue. Batch boundaries depend only on the grid, never on the
// thread count. Not thread-safe (the runner calls next() serially).
#pragma once
#include "kernels/grid.hpp"
#include "stream/stage.hpp"

namespace meshless {

class CellRowSource final : public Source {
public:
    Payload gives() const override { return Payload::cells; }
    explicit CellRowSource(const GridSpec& g);
    std::optional<Batch> next() override;
    std::int64_t rows_per_batch() const { return rows_per_batch_; }

private:
    std::int64_t rows_ = 0, rows_per_batch_ = 1, next_row_ = 0;
    std::uint64_t seq_ = 0;
};

}  // namespace meshless
