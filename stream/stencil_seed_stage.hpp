// The marching-stencil seed stage of the scattered-data isosurface (dissertation sections 5.4-5.6):
// turns a batch naming a range of stencils of one row (stream/stencil_source.hpp) into seeds
// (kernels/stencil_seeds.hpp: regularisation on the fly, local CGAL Delaunay, marching tetrahedra,
// barycentric lattice). Only the batch's stencils' points and tetrahedrizations exist while it runs
// (the runner bounds the batches in flight, stream/runner.hpp). The output batch (RecordKind::seed)
// goes to FieldProjectStage (stream/field_project_stage.hpp), in-process or across a pipe.
// Thread-safe: process() may run concurrently on distinct batches (statistics are atomics); the
// grid, bins, points and field must outlive the stage. Batches are independent, so outputs do not
// depend on the thread count.
#pragma once
#include <array>
#include <atomic>
#include <vector>

#include "kernels/stencil_seeds.hpp"
#include "stream/stage.hpp"

namespace meshless {

class StencilSeedStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::cells; }
    Payload gives(Payload) const override { return Payload::seeds; }
    /// n = lattice parameter (InvalidArgument unless 1..kMaxLatticeN).
    StencilSeedStage(const StencilInput& in, double iso, int n);
    void process(Batch& b) const override;
    StencilSeedStats stats() const;
    /// Wall time inside process(), summed over threads.
    double busy_seconds() const { return 1e-9 * static_cast<double>(busy_ns_.load()); }

private:
    StencilInput in_;
    double iso_;
    int n_;
    std::vector<std::array<double, 3>> lattice_;
    mutable std::array<std::atomic<std::int64_t>, StencilSeedStats::kCounters> st_{};
    mutable std::atomic<std::int64_t> busy_ns_{0};
};

}  // namespace meshless
