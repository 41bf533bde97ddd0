// The pull-based stage graph's three interfaces (docs/architecture.md): Source::next(), Stage::process(),
// Sink::consume(). One level of interfaces, no void* payloads.
//
// Threading: Source::next and Sink::consume are called from one thread at a time, in order;
// Stage::process may be called concurrently on different batches, so stages must keep per-call
// state local (counters are atomics or merged by the stage itself).
#pragma once
#include <optional>

#include "stream/batch.hpp"

namespace meshless {

class Source {
public:
    virtual ~Source() = default;
    /// The next batch, or nullopt at the end. Sets seq in increasing order.
    virtual std::optional<Batch> next() = 0;
    /// Offered a consumed batch (whatever record arrays the sink left in it) so that the source can
    /// reuse their capacity in its next batches; returns false when it does not want them (the
    /// default: the runner then recycles them itself). May be called from another thread than
    /// next(), never concurrently with itself.
    virtual bool recycle(Batch& consumed) {
        (void)consumed;
        return false;
    }
};

class Stage {
public:
    virtual ~Stage() = default;
    /// Transforms a batch in place (may change its kind). Thread-safe across distinct batches.
    virtual void process(Batch& b) const = 0;
};

class Sink {
public:
    virtual ~Sink() = default;
    /// Receives batches in increasing seq order.
    virtual void consume(Batch&& b) = 0;
    /// Receives a batch that the caller keeps (a tee hands the same batch to two sinks); the
    /// default copies it into consume(), sinks that only read a batch override it to avoid the copy.
    virtual void observe(const Batch& b) {
        Batch copy = b;
        consume(std::move(copy));
    }
    /// Called once after the last batch (write trailers, commit files).
    virtual void finish() {}
};

}  // namespace meshless
