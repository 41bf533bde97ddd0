#include "stream/cell_row_source.hpp"

#include <algorithm>

#include "kernels/cell_sampling.hpp"

namespace meshless {

CellRowSource::CellRowSource(const GridSpec& g) : rows_(cell_row_count(g)) {
    const std::int64_t cells_per_row = std::max<std::int64_t>(1, g.dims[0] - 1);
    rows_per_batch_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(kMaxBatchRecords) / cells_per_row);
}

std::optional<Batch> CellRowSource::next() {
    if (next_row_ >= rows_) return std::nullopt;
    Batch b;
    b.seq = seq_++;
    b.kind = RecordKind::sample;
    b.cells.k0 = next_row_;
    b.cells.k1 = std::min(rows_, next_row_ + rows_per_batch_);
    next_row_ = b.cells.k1;
    return b;
}

}  // namespace meshless
