// Naive per-block marching cubes as a stage graph (`meshless mc BLOCKS...`, the baseline of
// dissertation section 4.2 / Figures 4.6-4.8):
//   BlockMcSource (runs of cell layers of each block, blocks in order) -> BlockMcStage (one mesh
//   piece per batch, kernels/block_marching_cubes.hpp, per-triangle block id in Mesh::block) ->
//   MeshWeldSink (stream/mesh_sink.hpp: welds the vertices consecutive pieces of one block share).
// A batch's work is Batch::cells = [k0, k1) in the *global* layer numbering: the cell layers of
// block 0, then those of block 1, ... (a batch never spans two blocks). Seam keys
// (Batch::mesh_seam) are the block edge keys offset by 3 * (nodes of the earlier blocks), so they
// are unique over all blocks; only vertices on the batch's first or last node layer (shared with
// the neighbouring batch of the same block) carry one. The mesh is therefore each block's own
// welded marching-cubes mesh, blocks never welded to each other, in block order, cells in
// (i fastest, then j, then k) order: the same bytes for any --threads.
// Orientation: a first graph over the same work batches (block_census: BlockMcSource ->
// BlockCensusStage -> a discarding sink, in parallel) counts each block's cells by Jacobian sign;
// the marching-cubes stage contours the left-handed blocks with flipped winding.
// The multiblock must outlive source and stage. The source is not thread-safe (serial next()); the
// stage is (statistics are atomics).
#pragma once
#include <atomic>
#include <vector>

#include "kernels/block_marching_cubes.hpp"
#include "stream/stage.hpp"

namespace meshless {

class BlockMcSource final : public Source {
public:
    Payload gives() const override { return Payload::cells; }
    static constexpr std::int64_t kCellsPerBatch = std::int64_t{1} << 16;
    explicit BlockMcSource(const Multiblock& mb, std::int64_t cells_per_batch = kCellsPerBatch);
    std::optional<Batch> next() override;

private:
    struct Run {
        std::int64_t first_layer, layers, per;
    };
    std::vector<Run> runs_;  // per block
    std::size_t block_ = 0;
    std::int64_t at_ = 0;  // layer within the block
    std::uint64_t seq_ = 0;
};

struct BlockMcTotals {
    std::int64_t cells = 0, active_cells = 0, skipped_invalid = 0, skipped_degenerate = 0;
};

/// Per block, the Jacobian-sign census of its cells (kernels/block_marching_cubes.hpp
/// block_orientation), computed by a graph over BlockMcSource's batches on `threads` threads
/// (sums: the same result for any thread count).
std::vector<BlockOrientation> block_census(const Multiblock& mb, int threads);

class BlockMcStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::cells; }
    Payload gives(Payload) const override { return Payload::mesh; }
    /// census: block_census(mb, ...).
    BlockMcStage(const Multiblock& mb, double iso, std::vector<BlockOrientation> census);
    void process(Batch& b) const override;
    BlockMcTotals totals() const {
        return {cells_.load(), active_.load(), invalid_.load(), degenerate_.load()};
    }
    /// Per block: Jacobian-sign census of its cells.
    const std::vector<BlockOrientation>& orientation() const { return orient_; }

private:
    const Multiblock& mb_;
    double iso_;
    std::vector<BlockOrientation> orient_;
    std::vector<std::int64_t> first_layer_;  // per block, its first global layer (+ end sentinel)
    std::vector<std::uint64_t> key_base_;    // per block, 3 * nodes of the earlier blocks
    mutable std::atomic<std::int64_t> cells_{0}, active_{0}, invalid_{0}, degenerate_{0};
};

}  // namespace meshless
