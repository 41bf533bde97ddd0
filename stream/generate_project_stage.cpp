#include "stream/generate_project_stage.hpp"

namespace meshless {

void GenerateProjectStage::process(Batch& b) const {
    SamplingStats s;
    ProjectionStats ps;
    b.kind = RecordKind::point;
    b.points.clear();
    if (b.chunk) {  // slab-streamed: rows local to the chunk, positions offset by its first slice
        SamplingParams p = p_;
        p.index_offset[2] += b.chunk->z0;
        sample_and_project_active_cells(b.chunk->samples.view(), iso_, b.cells.k0, b.cells.k1, p, mode_, b.points, s, ps);
        b.chunk.reset();
    } else {
        sample_and_project_active_cells(v_, iso_, b.cells.k0, b.cells.k1, p_, mode_, b.points, s, ps);
    }
    b.cells = {};
    sampling_.add(s);
    projection_.add(ps);
}

}  // namespace meshless
