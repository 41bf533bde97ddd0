#include "stream/marching_cubes_stage.hpp"

#include <algorithm>

namespace meshless {

McSlabSource::McSlabSource(const GridSpec& g, std::int64_t cells_per_batch) {
    layers_ = std::max<std::int64_t>(0, g.dims[2] - 1);
    const std::int64_t per_layer = std::max<std::int64_t>(1, (g.dims[0] - 1) * (g.dims[1] - 1));
    per_ = std::max<std::int64_t>(1, cells_per_batch / per_layer);
}

std::optional<Batch> McSlabSource::next() {
    if (next_ >= layers_) return std::nullopt;
    Batch b;
    b.seq = seq_++;
    b.kind = RecordKind::mesh;
    b.cells = {next_, std::min(layers_, next_ + per_)};
    next_ = b.cells.k1;
    return b;
}

std::optional<Batch> McBrickSource::next() {
    if (at_ >= bricks_.size()) return std::nullopt;
    Batch b;
    b.seq = at_;
    b.kind = RecordKind::mesh;
    b.brick = static_cast<std::int64_t>(bricks_[at_++]);
    return b;
}

namespace {

/// Marks the vertices whose edge lies in one of the box's boundary planes (shared with a
/// neighbouring piece): an edge along `axis` lies in plane d = c (d != axis) when its index d is c.
void mark_seam(const std::vector<std::uint64_t>& keys, const std::array<std::int64_t, 3>& whole,
               const std::array<std::int64_t, 3>& lo, const std::array<std::int64_t, 3>& hi, std::vector<std::uint64_t>& seam) {
    seam.resize(keys.size());
    const std::uint64_t w0 = static_cast<std::uint64_t>(whole[0]), w1 = static_cast<std::uint64_t>(whole[1]);
    for (std::size_t v = 0; v < keys.size(); ++v) {
        const std::uint64_t e = keys[v] / 3;
        const int axis = static_cast<int>(keys[v] % 3);
        const std::int64_t g[3] = {static_cast<std::int64_t>(e % w0), static_cast<std::int64_t>((e / w0) % w1),
                                   static_cast<std::int64_t>(e / (w0 * w1))};
        bool on = false;
        for (int d = 0; d < 3 && !on; ++d) on = d != axis && (g[d] == lo[d] || g[d] == hi[d]);
        seam[v] = on ? keys[v] : Batch::kNoSeam;
    }
}

}  // namespace

void MarchingCubesStage::process(Batch& b) const {
    McStats st;
    std::vector<std::uint64_t> keys;
    if (b.brick >= 0) {
        const auto i = static_cast<std::size_t>(b.brick);
        const auto bytes = cache_->get(i);
        VolumeView v = cache_->view(i, *bytes);
        const GridSpec& whole = store_->info().grid;
        v.grid.origin = whole.origin;  // positions from global indices (bitwise equal across bricks)
        const auto first = store_->brick_first_voxel(i);
        b.mesh = marching_cubes_slab(v, iso_, 0, v.grid.dims[2] - 1, &st, first, &keys, whole.dims);
        const std::array<std::int64_t, 3> hi = {first[0] + v.grid.dims[0] - 1, first[1] + v.grid.dims[1] - 1,
                                                first[2] + v.grid.dims[2] - 1};
        mark_seam(keys, whole.dims, first, hi, b.mesh_seam);
    } else {
        b.mesh = marching_cubes_slab(v_, iso_, b.cells.k0, b.cells.k1, &st, {0, 0, 0}, &keys, v_.grid.dims);
        // only the slab's bottom and top sample slices are shared (with the slabs below and above)
        const std::array<std::int64_t, 3> lo = {-1, -1, b.cells.k0}, hi = {-1, -1, b.cells.k1};
        mark_seam(keys, v_.grid.dims, lo, hi, b.mesh_seam);
    }
    b.kind = RecordKind::mesh;
    b.cells = {};
    b.brick = -1;
    active_ += st.active_cells;
    nonfinite_ += st.skipped_nonfinite;
}

}  // namespace meshless
