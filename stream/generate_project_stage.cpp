#include "stream/generate_project_stage.hpp"

namespace meshless {

void GenerateProjectStage::process(Batch& b) const {
    SamplingStats s;
    ProjectionStats ps;
    b.kind = RecordKind::point;
    b.points.clear();
    sample_and_project_active_cells(v_, iso_, b.cells.k0, b.cells.k1, p_, mode_, b.points, s, ps);
    b.cells = {};
    active_ += s.active_cells;
    nonfinite_ += s.nonfinite_cells;
    input_ += ps.input;
    output_ += ps.output;
    too_far_ += ps.too_far;
    flat_ += ps.flat;
    missed_ += ps.missed;
}

ProjectionStats GenerateProjectStage::projection_stats() const {
    ProjectionStats s;
    s.input = input_.load();
    s.output = output_.load();
    s.too_far = too_far_.load();
    s.flat = flat_.load();
    s.missed = missed_.load();
    return s;
}

}  // namespace meshless
