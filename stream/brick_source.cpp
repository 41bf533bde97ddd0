#include "stream/brick_source.hpp"

#include <algorithm>

#include "kernels/cell_sampling.hpp"

namespace meshless {

BrickSource::BrickSource(const BrickStore& store, std::vector<std::size_t> bricks)
    : store_(store), bricks_(std::move(bricks)) {}

std::optional<Batch> BrickSource::next() {
    while (at_ < bricks_.size()) {
        const GridSpec g = store_.brick_grid(bricks_[at_]);
        const std::int64_t rows = cell_row_count(g);
        if (row_ >= rows) {
            ++at_;
            row_ = 0;
            continue;
        }
        const std::int64_t per = std::max<std::int64_t>(1, static_cast<std::int64_t>(kMaxBatchRecords) / std::max<std::int64_t>(1, g.dims[0] - 1));
        Batch b;
        b.seq = seq_++;
        b.kind = RecordKind::sample;
        b.brick = static_cast<std::int64_t>(bricks_[at_]);
        b.cells = {row_, std::min(rows, row_ + per)};
        row_ = b.cells.k1;
        return b;
    }
    return std::nullopt;
}

void BrickGenerateStage::process(Batch& b) const {
    const auto bytes = cache_.get(static_cast<std::size_t>(b.brick));
    VolumeView v = cache_.view(static_cast<std::size_t>(b.brick), *bytes);
    // positions from the whole volume's origin and global indices (see SamplingParams)
    SamplingParams p = p_;
    p.index_offset = store_.brick_first_voxel(static_cast<std::size_t>(b.brick));
    v.grid.origin = store_.info().grid.origin;
    SamplingStats s;
    if (fused_) {
        ProjectionStats ps;
        b.kind = RecordKind::point;
        b.points.clear();
        sample_and_project_active_cells(v, iso_, b.cells.k0, b.cells.k1, p, *fused_, b.points, s, ps);
        projection_.add(ps);
    } else {
        b.kind = RecordKind::sample;
        b.samples.clear();
        sample_active_cells(v, iso_, b.cells.k0, b.cells.k1, p, b.samples, s);
    }
    b.cells = {};
    b.brick = -1;
    sampling_.add(s);
}

}  // namespace meshless
