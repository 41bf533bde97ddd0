#include "stream/generate_stage.hpp"

namespace meshless {

void GenerateStage::process(Batch& b) const {
    SamplingStats s;
    b.kind = RecordKind::sample;
    b.samples.clear();
    if (b.chunk) {  // slab-streamed: rows local to the chunk, positions offset by its first slice
        SamplingParams p = p_;
        p.index_offset[2] += b.chunk->z0;
        sample_active_cells(b.chunk->samples.view(), iso_, b.cells.k0, b.cells.k1, p, b.samples, s);
        b.chunk.reset();
    } else {
        sample_active_cells(v_, iso_, b.cells.k0, b.cells.k1, p_, b.samples, s);
    }
    b.cells = {};
    stats_.add(s);
}

}  // namespace meshless
