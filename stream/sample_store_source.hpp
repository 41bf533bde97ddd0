// Paradigm (A) extraction as a stage-graph Source (dissertation section 3.5, Table 3.1): the
// active samples of one isovalue from a sample store (ooc/sample_store.hpp): the candidate cell
// rows from its span-space index, recomputed from its brick store, in batches of at most
// kMaxBatchRecords SampleRecords (kind sample, corners included). Batches follow the brick (Morton)
// and row order of paradigm (C), so the records equal, in order and bytes, those of
// `meshless generate vol.mlb`. A damaged bucket throws FormatError from the constructor, a damaged
// brick from next(). Not thread-safe (the runner calls next() serially); the store must outlive it.
#pragma once
#include <optional>

#include "ooc/sample_store.hpp"
#include "stream/stage.hpp"

namespace meshless {

class SampleStoreSource final : public Source {
public:
    Payload gives() const override { return Payload::samples; }
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
