// Marching cubes as a stage graph (the section-3.6 baseline, `meshless mc`):
//   McSlabSource (z-slabs of an in-memory volume) | McBrickSource (active bricks of a store, Morton
//   order) -> MarchingCubesStage (one mesh piece per batch, kernels/marching_cubes.hpp) ->
//   MeshWeldSink (stream/mesh_sink.hpp: welds the vertices pieces share, writes the PLY mesh).
// Batches of kind RecordKind::mesh carry the piece (local indices) and, per vertex on the piece's
// boundary, the key of its grid edge in the whole volume (Batch::mesh_seam; kNoSeam inside), which
// is all the sink needs to weld: a vertex on a shared edge is computed bitwise identically by both
// pieces (global indices), so welding by edge gives exactly the mesh of one pass over the volume
// (for slabs: the same bytes as marching_cubes(); for bricks: the same vertex set, in brick order,
// normals of seam vertices as the first brick computed them).
// Batch boundaries depend only on the grid (slabs) or the store and isovalue (bricks), so outputs
// are identical for any thread count. Sources are not thread-safe (serial next()); the stage is
// (statistics are atomics). The volume / store / cache must outlive them.
#pragma once
#include <atomic>
#include <vector>

#include "kernels/marching_cubes.hpp"
#include "ooc/brick_cache.hpp"
#include "stream/stage.hpp"

namespace meshless {

/// Batches naming z-layers of cells [cells.k0, cells.k1) (cell layer k = cells between sample
/// slices k and k+1), at most kMcCellsPerBatch cells (at least one layer) each.
class McSlabSource final : public Source {
public:
    Payload gives() const override { return Payload::cells; }
    static constexpr std::int64_t kMcCellsPerBatch = std::int64_t{1} << 18;
    explicit McSlabSource(const GridSpec& g, std::int64_t cells_per_batch = kMcCellsPerBatch);
    std::optional<Batch> next() override;

private:
    std::int64_t layers_ = 0, per_ = 1, next_ = 0;
    std::uint64_t seq_ = 0;
};

/// One batch per brick (Batch::brick = index into store.bricks()), in the given order.
class McBrickSource final : public Source {
public:
    Payload gives() const override { return Payload::cells; }
    explicit McBrickSource(std::vector<std::size_t> bricks) : bricks_(std::move(bricks)) {}
    std::optional<Batch> next() override;

private:
    std::vector<std::size_t> bricks_;
    std::size_t at_ = 0;
};

class MarchingCubesStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::cells; }
    Payload gives(Payload) const override { return Payload::mesh; }
    /// Slabs of an in-memory volume.
    MarchingCubesStage(VolumeView v, double iso) : v_(v), iso_(iso) {}
    /// Bricks of a store through the cache.
    MarchingCubesStage(const BrickStore& store, BrickCache& cache, double iso) : store_(&store), cache_(&cache), iso_(iso) {}
    void process(Batch& b) const override;
    McStats stats() const { return {active_.load(), nonfinite_.load()}; }

private:
    VolumeView v_;
    const BrickStore* store_ = nullptr;
    BrickCache* cache_ = nullptr;
    double iso_;
    mutable std::atomic<std::int64_t> active_{0}, nonfinite_{0};
};

}  // namespace meshless
