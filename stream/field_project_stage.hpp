// The stage that projects seeds onto the isosurface f = iso of any `const Field&` (docs/architecture.md "What the
// graph carries": Newton onto a Field, the projector chapters 4, 5 and 7 plug into), by
// kernels/field_newton_projection.hpp, one Field::evaluate per Newton round per batch.
//
// Input: a batch of points (seed = position) or of samples (seed = sample position). Output: a point
// batch, in input order, holding the seeds that converged: position on the surface, unit normal
// = -grad f / |grad f| (pointing to decreasing values, VTK's convention, as every PointRecord in this project: see
// kernels/records.hpp and kernels/project_sample.hpp), the seed's radius passed through, value = iso.
// Seeds that did not converge are dropped and counted (stats()); a point batch's block ids
// (Batch::point_block) follow the points that stay. With `limit_to_cell`, a sample's
// displacement is also limited to half its cell's diagonal (the criterion of Fig. 3.3), when the
// cell size is finite and positive.
// A batch of multiblock seeds (RecordKind::seed, kernels/block_cell_seeds.hpp; dissertation section
// 4.4) is projected with a tolerance relative to each seed's cell: seed_tolerance x cell diagonal
// (the dissertation's 0.01), and at most seed_max_travel cell diagonals from the seed (too_far
// otherwise), taking the last within-tolerance step (seed_final_step, so points seeded in different
// blocks agree far better than the tolerance); each converged point gets the radius 2 (1 + d/l) base_radius
// (kernels/multiblock_splat_radius.hpp, d = distance travelled, l = cell diagonal), value = iso,
// and the seed's block id in Batch::point_block.
// busy_seconds(): wall time spent inside process(), summed over the threads (for points/s/core).
// Thread-safe: process() may run concurrently on distinct batches; statistics are atomics. The
// field must outlive the stage. Batches are processed independently, so outputs are identical for
// any thread count.
#pragma once
#include <atomic>
#include <limits>

#include "kernels/field.hpp"
#include "kernels/field_newton_projection.hpp"
#include "stream/stage.hpp"

namespace meshless {

class AtomicFieldNewtonStats {
public:
    void add(const FieldNewtonStats& s);
    FieldNewtonStats load() const;

private:
    std::atomic<std::int64_t> v_[8] = {};
};

struct FieldProjectParams {
    FieldNewtonParams newton;
    bool limit_to_cell = false;  ///< samples: also limit displacement to half the cell diagonal
    double seed_tolerance = 0.01;  ///< seeds: tolerance = seed_tolerance x the seed's cell diagonal
    double seed_max_travel = std::numeric_limits<double>::infinity();  ///< seeds: limit, in cell diagonals
    bool seed_final_step = true;  ///< seeds: take the last (within-tolerance) Newton step (FieldNewtonParams::final_step)
};

class FieldProjectStage final : public Stage {
public:
    PayloadSet takes() const override { return {Payload::samples, Payload::points, Payload::seeds}; }
    Payload gives(Payload) const override { return Payload::points; }
    FieldProjectStage(const Field& f, double iso, FieldProjectParams p = {}) : f_(f), iso_(iso), p_(p) {}
    void process(Batch& b) const override;
    FieldNewtonStats stats() const { return stats_.load(); }
    double busy_seconds() const { return 1e-9 * static_cast<double>(busy_ns_.load()); }

private:
    void process_seeds(Batch& b) const;
    const Field& f_;
    double iso_;
    FieldProjectParams p_;
    mutable AtomicFieldNewtonStats stats_;
    mutable std::atomic<std::int64_t> busy_ns_{0};
};

}  // namespace meshless
