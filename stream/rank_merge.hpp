// Streaming several ranks' outputs into one sink in the single-process order (docs/architecture.md
// "Distribution"), without the root holding the output.
//
// The work is a sequence of n *units* (for `isosurface`: the active bricks in Morton order), dealt
// round-robin (unit u belongs to rank u % ranks) or on request by rank 0 (stream/unit_deal.hpp). Every rank runs its own graph over its units; a
// TaggingSource records, in order, the unit of each batch it emits. Rank r > 0 ends its graph with a
// RankSendSink, which sends each batch's points to rank 0 as one message and an END message after
// each of its units (so units that produce no batch are still closed). Rank 0 ends its graph with a
// RankMergeSink, which writes the units to the downstream sink in unit order: its own batches as they
// come, every other unit received from its owner, message by message, when its turn comes. The
// downstream sink therefore sees the single-process sequence of points, in batches.
//
// Memory: rank 0 holds one received message (at most one batch, kMaxBatchRecords points) at a time;
// a sender holds at most the channel's window of messages; neither grows with the output.
// Messages: a 24-byte header {u32 kind (1 data, 2 end), u32 rank, u64 unit, u64 count} followed by
// count PointRecords (data only). A message that does not match what rank 0 expects throws
// FormatError naming the rank and the unit.
// Threading: sinks and sources here follow stage.hpp (serial next()/consume()); UnitTags is the one
// object shared between the source's and the sink's threads (mutex inside).
#pragma once
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <vector>

#include "stream/stage.hpp"

namespace meshless {

/// Byte messages between ranks, in order per pair of ranks (what MPI guarantees for one tag).
class RankChannel {
public:
    virtual ~RankChannel() = default;
    /// Sends to rank 0; may block while the sender's window of unreceived messages is full.
    virtual void send_to_root(std::vector<std::byte> message) = 0;
    /// The next message from `rank` (blocking), into `message` (resized).
    virtual void receive_from(int rank, std::vector<std::byte>& message) = 0;
    /// Blocks until every message sent has been received.
    virtual void flush() = 0;

    // The dynamic deal (stream/unit_deal.hpp: the dissertation's master/worker). A rank may call
    // request_unit from another thread than send_to_root, and rank 0 poll_request/grant from another
    // thread than receive_from.
    /// Rank r > 0: asks rank 0 for a unit and waits for the answer (nullopt: none is left).
    virtual std::optional<std::size_t> request_unit() = 0;
    /// Rank 0: takes one waiting request and returns its rank; nullopt when none waits (never blocks).
    virtual std::optional<int> poll_request() = 0;
    /// Rank 0: answers `rank`'s request with a unit, or nullopt for "none is left".
    virtual void grant(int rank, std::optional<std::size_t> unit) = 0;
};

/// The rank that owns unit u of a round-robin deal over `ranks` ranks.
inline int unit_owner(std::size_t unit, int ranks) { return static_cast<int>(unit % static_cast<std::size_t>(ranks)); }
/// The units of `rank`, in increasing order.
std::vector<std::size_t> units_of_rank(std::size_t units, int rank, int ranks);

/// A rank's units in increasing order: all of them (a static deal), or appended as they are dealt
/// (a dynamic one). Thread-safe: the source appends while the sink reads.
class UnitList {
public:
    UnitList() = default;
    explicit UnitList(std::vector<std::size_t> units) : u_(std::move(units)) {}
    /// Appends a unit; throws FormatError unless it exceeds the last (a corrupt deal).
    void push(std::size_t unit);
    /// The i-th unit, nullopt while there is none (yet).
    std::optional<std::size_t> at(std::size_t i) const;

private:
    mutable std::mutex mu_;
    std::vector<std::size_t> u_;
};

/// The unit of each batch a TaggingSource emitted, in emission order, until its sink consumes it.
class UnitTags {
public:
    void push(std::size_t unit);
    std::size_t pop();  ///< throws std::logic_error when empty (a sink got a batch no source emitted)

private:
    std::mutex mu_;
    std::deque<std::size_t> q_;
};

/// Wraps a source and records unit_of(batch) for each batch it emits.
class TaggingSource final : public Source {
public:
    Payload gives() const override { return inner_.gives(); }
    TaggingSource(Source& inner, UnitTags& tags, std::function<std::size_t(const Batch&)> unit_of)
        : inner_(inner), tags_(tags), unit_of_(std::move(unit_of)) {}
    std::optional<Batch> next() override;

private:
    Source& inner_;
    UnitTags& tags_;
    std::function<std::size_t(const Batch&)> unit_of_;
};

/// Rank r > 0: the point batches of its units (in increasing unit order) to rank 0.
class RankSendSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    /// A static deal: the rank's units, all known.
    RankSendSink(RankChannel& ch, UnitTags& tags, int rank, std::vector<std::size_t> my_units);
    /// A dynamic deal: `my_units` grows as the rank's source is dealt units (it must hold every unit
    /// of a batch before the batch reaches this sink, and all of them at finish()).
    RankSendSink(RankChannel& ch, UnitTags& tags, int rank, const UnitList& my_units);
    void consume(Batch&& b) override;
    void finish() override;

private:
    void end_units_before(std::size_t unit);
    RankChannel& ch_;
    UnitTags& tags_;
    int rank_;
    UnitList own_;
    const UnitList& units_;
    std::size_t next_ = 0;  ///< index in units_ of the unit being sent
};

/// Rank 0: its own batches and the other ranks' messages, in unit order, into `out`.
class RankMergeSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    /// A static deal: unit u is rank unit_owner(u, ranks)'s.
    RankMergeSink(RankChannel& ch, UnitTags& tags, std::size_t units, int ranks, Sink& out)
        : RankMergeSink(ch, tags, units, [ranks](std::size_t u) { return unit_owner(u, ranks); }, out) {}
    /// Any deal: owner(u) is the rank of unit u, called only once u and every unit before it are dealt.
    RankMergeSink(RankChannel& ch, UnitTags& tags, std::size_t units, std::function<int(std::size_t)> owner, Sink& out)
        : ch_(ch), tags_(tags), units_(units), owner_(std::move(owner)), out_(out) {}
    void consume(Batch&& b) override;
    /// Receives the remaining units, then calls out.finish().
    void finish() override;
    std::uint64_t points() const { return points_; }
    std::uint64_t received_messages() const { return messages_; }

private:
    void write_units_before(std::size_t unit);
    void receive_unit(std::size_t unit);
    void deliver(Batch&& b);
    RankChannel& ch_;
    UnitTags& tags_;
    std::size_t units_;
    std::function<int(std::size_t)> owner_;
    Sink& out_;
    std::size_t next_unit_ = 0;  ///< the unit being written
    std::uint64_t seq_ = 0, points_ = 0, messages_ = 0;
    std::vector<std::byte> buf_;
};

}  // namespace meshless
