// The marching-cubes seed stage of the multiblock/AMR isosurface (dissertation section 4.4): turns a
// batch naming a range of cells of one block (stream/block_cell_source.hpp) into seeds: per cell
// its marching-cubes triangles in physical space, per triangle the barycentric lattice of n(n+1)/2
// samples (kernels/block_cell_seeds.hpp). Cells with an invalid corner and collapsed/inverted cells
// are skipped and counted; each block is oriented by its plan's majority Jacobian sign. The output
// batch (RecordKind::seed) goes to FieldProjectStage (stream/field_project_stage.hpp), in-process or
// across a pipe (formats/point_stream.hpp, seed records).
// Thread-safe: process() may run concurrently on distinct batches (statistics are atomics); the
// multiblock and the plan must outlive the stage. Batches are independent, so outputs do not depend
// on the thread count.
#pragma once
#include <array>
#include <atomic>
#include <vector>

#include "kernels/block_cell_seeds.hpp"
#include "stream/stage.hpp"

namespace meshless {

class BlockSeedStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::cells; }
    Payload gives(Payload) const override { return Payload::seeds; }
    /// plan = plan_block_seeds(mb, iso); n = lattice parameter (InvalidArgument unless 1..kMaxLatticeN).
    BlockSeedStage(const Multiblock& mb, const BlockSeedPlan& plan, double iso, int n);
    void process(Batch& b) const override;
    BlockSeedStats stats() const;
    /// Wall time inside process(), summed over threads.
    double busy_seconds() const { return 1e-9 * static_cast<double>(busy_ns_.load()); }
    int lattice_n() const { return n_; }

private:
    const Multiblock& mb_;
    const BlockSeedPlan& plan_;
    double iso_;
    int n_;
    std::vector<std::array<double, 3>> lattice_;
    mutable std::array<std::atomic<std::int64_t>, 8> st_{};
    mutable std::atomic<std::int64_t> busy_ns_{0};
};

}  // namespace meshless
