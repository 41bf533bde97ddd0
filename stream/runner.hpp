// The runner of the pull-based stage graph (docs/architecture.md): pulls batches from a Source, runs the
// Stages on them (in parallel across batches when threads > 1, oneTBB parallel_pipeline with a
// bounded number of batches in flight = 2 * threads), and delivers them to the Sink in sequence
// order, so the sink's bytes do not depend on the thread count. The record arrays of consumed
// batches are handed to new batches (their capacity reused, at most one per batch in flight), so a
// long run allocates no new batch memory after its first batches. Exceptions from any stage are
// rethrown to the caller (the first one wins); the sink's finish() is not called then.
#pragma once
#include <span>

#include "stream/stage.hpp"

namespace meshless {

struct RunOptions {
    int threads = 1;  ///< worker threads; <= 0 means available_cpus() (stream/available_cpus.hpp)
};

void run_pipeline(Source& source, std::span<const Stage* const> stages, Sink& sink,
                  const RunOptions& opt = {});

}  // namespace meshless
