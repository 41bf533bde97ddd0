#include "stream/generate_stage.hpp"

namespace meshless {

void GenerateStage::process(Batch& b) const {
    SamplingStats s;
    b.kind = RecordKind::sample;
    b.samples.clear();
    sample_active_cells(v_, iso_, b.cells.k0, b.cells.k1, p_, b.samples, s);
    b.cells = {};
    stats_.add(s);
}

}  // namespace meshless
