#include "stream/stencil_source.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace meshless {

StencilSource::StencilSource(const StencilGrid& grid, std::int64_t per_unit) : StencilSource(grid, 0, grid.total(), per_unit) {}

StencilSource::StencilSource(const StencilGrid& grid, std::int64_t first, std::int64_t last, std::int64_t per_unit)
    : row_(std::max<std::int64_t>(1, grid.count[0])), per_(std::max<std::int64_t>(1, per_unit)), at_(std::max<std::int64_t>(0, first)),
      end_(std::min(last, grid.total())) {}

StencilSource::StencilSource(const StencilGrid& grid, std::vector<std::size_t> rows, std::int64_t per_unit)
    : StencilSource(grid, [rows = std::move(rows), i = std::size_t{0}]() mutable -> std::optional<std::size_t> {
          if (i >= rows.size()) return std::nullopt;
          return rows[i++];
      }, per_unit) {}

StencilSource::StencilSource(const StencilGrid& grid, std::function<std::optional<std::size_t>()> next_row, std::int64_t per_unit)
    : row_(std::max<std::int64_t>(1, grid.count[0])), per_(std::max<std::int64_t>(1, per_unit)), at_(0), end_(0),
      rows_total_(grid.count[0] > 0 ? grid.total() / grid.count[0] : 0), next_row_(std::move(next_row)) {}

std::optional<Batch> StencilSource::next() {
    if (next_row_ && at_ >= end_) {
        const std::optional<std::size_t> r = next_row_();
        if (!r) return std::nullopt;
        if (*r >= static_cast<std::size_t>(rows_total_))
            throw std::out_of_range("stencil source: row " + std::to_string(*r) + " beyond the grid's " + std::to_string(rows_total_));
        at_ = static_cast<std::int64_t>(*r) * row_;
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
