// Paradigm (A) extraction as a stage-graph Source (dissertation section 3.5, Table 3.1): the
// active samples of one isovalue read from a sample store (ooc/sample_store.hpp), in batches of at
// most kMaxBatchRecords SampleRecords (kind sample, corner[] = NaN: only the approximate projection
// applies). Batches follow the store's bucket order, so the output is the same for any thread
// count of the runner. A damaged bucket throws FormatError from next(). Not thread-safe (the
// runner calls next() serially); the store must outlive the source.
#pragma once
#include <optional>

#include "ooc/sample_store.hpp"
#include "stream/stage.hpp"

namespace meshless {

class SampleStoreSource final : public Source {
public:
    SampleStoreSource(const SampleStore& store, double iso, const SamplingParams& params = {})
        : query_(store, iso, params) {}
    std::optional<Batch> next() override;
    /// Samples emitted so far.
    std::uint64_t emitted() const { return query_.emitted(); }

private:
    SampleQuery query_;
    std::uint64_t seq_ = 0;
};

}  // namespace meshless
