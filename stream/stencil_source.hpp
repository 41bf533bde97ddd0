// Source of the scattered-data seed work (dissertation sections 5.4-5.6, the "marching stencil"):
// batches naming a range of stencils of one stencil row, as linear stencil indices
// [cells.k0, cells.k1) (kernels/marching_stencils.hpp: s = sx + Sx (sy + Sy sz)), at most
// `per_unit` stencils each. A row's stencils share one regularised block of cells
// (kernels/stencil_regularisation.hpp), so units never span two rows. Sequence numbers are dense,
// the order is row by row; the ranges depend only on the grid and per_unit, never on the thread
// count. A batch's seeds are those of its stencils: usually far fewer than kMaxBatchRecords, more
// only when a stencil holds many thousands of points (pathological distributions, section 5.8).
// Not thread-safe (the runner calls next() serially).
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "kernels/marching_stencils.hpp"
#include "stream/stage.hpp"

namespace meshless {

/// Stencils per work unit: 8 (a few Delaunay tetrahedrizations; small units balance the threads,
/// and each unit regularises its cells in one Field::evaluate call).
inline constexpr std::int64_t kStencilsPerUnit = 8;

class StencilSource final : public Source {
public:
    Payload gives() const override { return Payload::cells; }
    /// The work of stencil range [first, last) in whole rows: first and last are multiples of the
    /// row length Sx (the MPI ranks' ranges), or 0 and grid.total() for all.
    StencilSource(const StencilGrid& grid, std::int64_t per_unit = kStencilsPerUnit);
    StencilSource(const StencilGrid& grid, std::int64_t first, std::int64_t last, std::int64_t per_unit = kStencilsPerUnit);
    /// The work of the listed stencil rows only (increasing row indices r = sy + Sy sz: the units an
    /// MPI rank owns, stream/stencil_ranks.hpp), each split as above.
    StencilSource(const StencilGrid& grid, std::vector<std::size_t> rows, std::int64_t per_unit = kStencilsPerUnit);
    /// The work of the rows next_row() names, asked for one at a time as the last one is used up
    /// (increasing, < the grid's row count; nullopt: no more): a rank of a dynamic deal
    /// (stream/unit_deal.hpp). Throws std::out_of_range for a row beyond the grid.
    StencilSource(const StencilGrid& grid, std::function<std::optional<std::size_t>()> next_row,
                  std::int64_t per_unit = kStencilsPerUnit);
    std::optional<Batch> next() override;
    std::uint64_t emitted() const { return seq_; }

private:
    std::int64_t row_, per_, at_, end_, rows_total_ = 0;
    std::function<std::optional<std::size_t>()> next_row_;  ///< when set: the rows still to emit after the current one
    std::uint64_t seq_ = 0;
};

}  // namespace meshless
