// The pull-based stage graph's three interfaces (docs/architecture.md): Source::next(), Stage::process(),
// Sink::consume(). One level of interfaces, no void* payloads.
//
// Typed graphs (stream/payload.hpp): each Source declares the payload it gives, each Stage the payloads
// it takes and what it gives for each, each Sink what it takes. run_pipeline checks the chain before the
// first batch (check_graph) and every delivered batch against the declared payload, so a recipe that
// joins stages wrongly fails at once with GraphError, whatever its data.
//
// Threading: Source::next and Sink::consume are called from one thread at a time, in order;
// Stage::process may be called concurrently on different batches, so stages must keep per-call
// state local (counters are atomics or merged by the stage itself).
#pragma once
#include <optional>
#include <typeinfo>
#include <span>
#include <stdexcept>
#include <string>

#include "stream/batch.hpp"
#include "stream/payload.hpp"

namespace meshless {

class Source {
public:
    virtual ~Source() = default;
    /// The next batch, or nullopt at the end. Sets seq in increasing order.
    virtual std::optional<Batch> next() = 0;
    /// The payload of every batch next() returns.
    virtual Payload gives() const = 0;
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
    /// The payloads process() accepts.
    virtual PayloadSet takes() const = 0;
    /// The payload of a batch after process(), given one of takes().
    virtual Payload gives(Payload given) const = 0;
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
    /// The payloads consume() accepts.
    virtual PayloadSet takes() const = 0;
};

/// A stage graph whose declared payloads do not chain, or a stage that delivered another payload than
/// it declared: a programming error in a recipe (the CLI maps it to exit 3), never bad input.
struct GraphError : std::logic_error {
    using std::logic_error::logic_error;
};

/// The payload that reaches the sink of source -> stages -> sink; throws GraphError naming the first
/// link whose payload the next one does not take ("ProjectStage takes samples, CellRowSource gives
/// cell rows").
Payload check_graph(const Source& source, std::span<const Stage* const> stages, const Sink& sink);

/// A class's name for messages ("ProjectStage"), without its namespace.
std::string graph_node_name(const std::type_info& t);

}  // namespace meshless
