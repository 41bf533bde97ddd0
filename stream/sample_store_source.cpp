#include "stream/sample_store_source.hpp"

namespace meshless {

std::optional<Batch> SampleStoreSource::next() {
    Batch b;
    b.kind = RecordKind::sample;
    if (!query_.next(b.samples, kMaxBatchRecords)) return std::nullopt;
    b.seq = seq_++;
    return b;
}

}  // namespace meshless
