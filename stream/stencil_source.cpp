#include "stream/stencil_source.hpp"

#include <algorithm>

namespace meshless {

StencilSource::StencilSource(const StencilGrid& grid, std::int64_t per_unit) : StencilSource(grid, 0, grid.total(), per_unit) {}

StencilSource::StencilSource(const StencilGrid& grid, std::int64_t first, std::int64_t last, std::int64_t per_unit)
    : row_(std::max<std::int64_t>(1, grid.count[0])), per_(std::max<std::int64_t>(1, per_unit)), at_(std::max<std::int64_t>(0, first)),
      end_(std::min(last, grid.total())) {}

StencilSource::StencilSource(const StencilGrid& grid, std::vector<std::size_t> rows, std::int64_t per_unit)
    : row_(std::max<std::int64_t>(1, grid.count[0])), per_(std::max<std::int64_t>(1, per_unit)), at_(0), end_(0), rows_(std::move(rows)),
      listed_(true) {}

std::optional<Batch> StencilSource::next() {
    if (listed_ && at_ >= end_) {
        if (next_row_ >= rows_.size()) return std::nullopt;
        at_ = static_cast<std::int64_t>(rows_[next_row_++]) * row_;
        end_ = at_ + row_;
    }
    if (at_ >= end_) return std::nullopt;
    Batch b;
    b.seq = seq_++;
    b.kind = RecordKind::seed;
    b.cells.k0 = at_;
    const std::int64_t row_end = (at_ / row_ + 1) * row_;
    b.cells.k1 = std::min({end_, row_end, at_ + per_});
    at_ = b.cells.k1;
    return b;
}

}  // namespace meshless
