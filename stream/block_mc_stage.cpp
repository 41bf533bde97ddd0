#include "stream/block_mc_stage.hpp"

#include <algorithm>

#include <stdexcept>

#include "kernels/errors.hpp"
#include "stream/runner.hpp"

namespace meshless {

namespace {
std::int64_t cell_layers(const StructuredBlock& b) {
    if (b.dims[0] < 2 || b.dims[1] < 2 || b.dims[2] < 2) return 0;
    return b.dims[2] - 1;
}
}  // namespace

BlockMcSource::BlockMcSource(const Multiblock& mb, std::int64_t cells_per_batch) {
    std::int64_t first = 0;
    for (const auto& b : mb.blocks) {
        const std::int64_t layers = cell_layers(b);
        const std::int64_t per_layer = std::max<std::int64_t>(1, (b.dims[0] - 1) * (b.dims[1] - 1));
        runs_.push_back({first, layers, std::max<std::int64_t>(1, cells_per_batch / per_layer)});
        first += layers;
    }
}

std::optional<Batch> BlockMcSource::next() {
    while (block_ < runs_.size() && at_ >= runs_[block_].layers) {
        ++block_;
        at_ = 0;
    }
    if (block_ >= runs_.size()) return std::nullopt;
    const Run& r = runs_[block_];
    Batch b;
    b.seq = seq_++;
    b.kind = RecordKind::mesh;
    const std::int64_t end = std::min(r.layers, at_ + r.per);
    b.cells = {r.first_layer + at_, r.first_layer + end};
    at_ = end;
    return b;
}

namespace {

/// The global layer -> block map shared by the stages.
std::size_t block_of(const std::vector<std::int64_t>& first_layer, std::int64_t k0) {
    const auto it = std::upper_bound(first_layer.begin(), first_layer.end() - 1, k0);
    return static_cast<std::size_t>(it - first_layer.begin()) - 1;
}

std::vector<std::int64_t> first_layers(const Multiblock& mb) {
    std::vector<std::int64_t> f;
    std::int64_t first = 0;
    for (const auto& b : mb.blocks) {
        f.push_back(first);
        first += cell_layers(b);
    }
    f.push_back(first);
    return f;
}

class CensusStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::cells; }
    Payload gives(Payload) const override { return Payload::cells; }
    explicit CensusStage(const Multiblock& mb) : mb_(mb), first_(first_layers(mb)), sums_(4 * mb.blocks.size()) {}
    void process(Batch& b) const override {
        const std::size_t blk = block_of(first_, b.cells.k0);
        const BlockOrientation o =
            block_orientation(mb_.blocks[blk], b.cells.k0 - first_[blk], b.cells.k1 - first_[blk]);
        sums_[4 * blk] += o.positive;
        sums_[4 * blk + 1] += o.negative;
        sums_[4 * blk + 2] += o.degenerate;
        sums_[4 * blk + 3] += o.invalid;
        b.cells = {};
    }
    std::vector<BlockOrientation> result() const {
        std::vector<BlockOrientation> r(mb_.blocks.size());
        for (std::size_t i = 0; i < r.size(); ++i)
            r[i] = {sums_[4 * i].load(), sums_[4 * i + 1].load(), sums_[4 * i + 2].load(), sums_[4 * i + 3].load()};
        return r;
    }

private:
    const Multiblock& mb_;
    std::vector<std::int64_t> first_;
    mutable std::vector<std::atomic<std::int64_t>> sums_;
};

class DiscardSink final : public Sink {
public:
    PayloadSet takes() const override { return PayloadSet::any(); }
    void consume(Batch&&) override {}
    void observe(const Batch&) override {}
};

}  // namespace

std::vector<BlockOrientation> block_census(const Multiblock& mb, int threads) {
    BlockMcSource source(mb);
    const CensusStage census(mb);
    DiscardSink sink;
    const Stage* stages[] = {&census};
    run_pipeline(source, stages, sink, {threads});
    return census.result();
}

BlockMcStage::BlockMcStage(const Multiblock& mb, double iso, std::vector<BlockOrientation> census)
    : mb_(mb), iso_(iso), orient_(std::move(census)) {
    if (orient_.size() != mb.blocks.size())
        throw std::invalid_argument("BlockMcStage: a census of " + std::to_string(orient_.size()) + " blocks for " +
                                    std::to_string(mb.blocks.size()));
    std::int64_t first = 0;
    std::uint64_t base = 0;
    for (const auto& b : mb.blocks) {
        first_layer_.push_back(first);
        key_base_.push_back(base);
        first += cell_layers(b);
        base += 3 * static_cast<std::uint64_t>(b.node_count());
    }
    first_layer_.push_back(first);
}

void BlockMcStage::process(Batch& b) const {
    // the block holding global layer k0 (batches never span blocks)
    const std::size_t blk = block_of(first_layer_, b.cells.k0);
    const StructuredBlock& sb = mb_.blocks[blk];
    const std::int64_t k0 = b.cells.k0 - first_layer_[blk], k1 = b.cells.k1 - first_layer_[blk];
    BlockMcStats st;
    std::vector<std::uint64_t> keys;
    b.mesh = block_marching_cubes(sb, iso_, orient_[blk].left_handed(), k0, k1, static_cast<std::uint32_t>(blk), st, keys);
    // Vertices on edges in node layer k0 or k1 (edges along i or j there) are shared with the
    // neighbouring batches of the block; weld keys offset by the block's base.
    const std::uint64_t layer = 3 * static_cast<std::uint64_t>(sb.dims[0] * sb.dims[1]);
    b.mesh_seam.resize(keys.size());
    for (std::size_t v = 0; v < keys.size(); ++v) {
        const std::uint64_t axis = keys[v] % 3;
        const auto k = static_cast<std::int64_t>(keys[v] / layer);
        b.mesh_seam[v] = (axis != 2 && (k == k0 || k == k1)) ? key_base_[blk] + keys[v] : Batch::kNoSeam;
    }
    b.cells = {};
    cells_ += st.cells;
    active_ += st.active_cells;
    invalid_ += st.skipped_invalid;
    degenerate_ += st.skipped_degenerate;
}

}  // namespace meshless
