#include "stream/rank_merge.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr std::uint32_t kData = 1, kEnd = 2;

struct MessageHeader {
    std::uint32_t kind;
    std::uint32_t rank;
    std::uint64_t unit;
    std::uint64_t count;
};
static_assert(sizeof(MessageHeader) == 24);

std::vector<std::byte> message(std::uint32_t kind, int rank, std::size_t unit, const std::vector<PointRecord>* pts) {
    const std::size_t n = pts ? pts->size() : 0;
    std::vector<std::byte> m(sizeof(MessageHeader) + n * sizeof(PointRecord));
    const MessageHeader h{kind, static_cast<std::uint32_t>(rank), unit, n};
    std::memcpy(m.data(), &h, sizeof h);
    if (n) std::memcpy(m.data() + sizeof h, pts->data(), n * sizeof(PointRecord));
    return m;
}

}  // namespace

std::vector<std::size_t> units_of_rank(std::size_t units, int rank, int ranks) {
    std::vector<std::size_t> u;
    for (std::size_t i = static_cast<std::size_t>(rank); i < units; i += static_cast<std::size_t>(ranks)) u.push_back(i);
    return u;
}

void UnitList::push(std::size_t unit) {
    std::lock_guard lock(mu_);
    if (!u_.empty() && unit <= u_.back())
        throw FormatError("rank merge: unit " + std::to_string(unit) + " dealt after unit " + std::to_string(u_.back()));
    u_.push_back(unit);
}

std::optional<std::size_t> UnitList::at(std::size_t i) const {
    std::lock_guard lock(mu_);
    if (i >= u_.size()) return std::nullopt;
    return u_[i];
}

void UnitTags::push(std::size_t unit) {
    std::lock_guard lock(mu_);
    q_.push_back(unit);
}

std::size_t UnitTags::pop() {
    std::lock_guard lock(mu_);
    if (q_.empty()) throw std::logic_error("rank merge: a batch reached the sink that no tagging source emitted");
    const std::size_t u = q_.front();
    q_.pop_front();
    return u;
}

std::optional<Batch> TaggingSource::next() {
    auto b = inner_.next();
    if (b) tags_.push(unit_of_(*b));
    return b;
}

RankSendSink::RankSendSink(RankChannel& ch, UnitTags& tags, int rank, std::vector<std::size_t> my_units)
    : ch_(ch), tags_(tags), rank_(rank), own_(std::move(my_units)), units_(own_) {}

RankSendSink::RankSendSink(RankChannel& ch, UnitTags& tags, int rank, const UnitList& my_units)
    : ch_(ch), tags_(tags), rank_(rank), units_(my_units) {}

void RankSendSink::end_units_before(std::size_t unit) {
    for (auto u = units_.at(next_); u && *u < unit; u = units_.at(++next_)) ch_.send_to_root(message(kEnd, rank_, *u, nullptr));
}

void RankSendSink::consume(Batch&& b) {
    const std::size_t unit = tags_.pop();
    end_units_before(unit);
    if (units_.at(next_) != unit)
        throw std::logic_error("rank merge: rank " + std::to_string(rank_) + " got a batch of unit " + std::to_string(unit) +
                               " it does not own or already closed");
    ch_.send_to_root(message(kData, rank_, unit, &b.points));
}

void RankSendSink::finish() {
    end_units_before(static_cast<std::size_t>(-1));
    ch_.flush();
}

void RankMergeSink::deliver(Batch&& b) {
    b.seq = seq_++;
    points_ += b.points.size();
    out_.consume(std::move(b));
}

void RankMergeSink::receive_unit(std::size_t unit) {
    const int from = owner_(unit);
    const std::string who = "MPI stream from rank " + std::to_string(from) + ", unit " + std::to_string(unit);
    for (;;) {
        ch_.receive_from(from, buf_);
        ++messages_;
        MessageHeader h;
        if (buf_.size() < sizeof h) throw FormatError(who + ": message of " + std::to_string(buf_.size()) + " bytes, shorter than its header");
        std::memcpy(&h, buf_.data(), sizeof h);
        if (h.rank != static_cast<std::uint32_t>(from) || h.unit != unit || (h.kind != kData && h.kind != kEnd))
            throw FormatError(who + ": got kind " + std::to_string(h.kind) + " of rank " + std::to_string(h.rank) + ", unit " +
                              std::to_string(h.unit));
        if (h.kind == kEnd) return;
        if (h.count > kMaxBatchRecords || buf_.size() != sizeof h + h.count * sizeof(PointRecord))
            throw FormatError(who + ": " + std::to_string(buf_.size()) + " bytes do not hold " + std::to_string(h.count) + " points");
        Batch b;
        b.kind = RecordKind::point;
        b.points.resize(h.count);
        if (h.count) std::memcpy(b.points.data(), buf_.data() + sizeof h, h.count * sizeof(PointRecord));
        deliver(std::move(b));
    }
}

void RankMergeSink::write_units_before(std::size_t unit) {
    // rank 0's own units before `unit` are complete (their batches came earlier); others' come now
    for (; next_unit_ < unit && next_unit_ < units_; ++next_unit_)
        if (owner_(next_unit_) != 0) receive_unit(next_unit_);
}

void RankMergeSink::consume(Batch&& b) {
    const std::size_t unit = tags_.pop();
    if (unit < next_unit_ || owner_(unit) != 0)
        throw std::logic_error("rank merge: rank 0 got a batch of unit " + std::to_string(unit) + " out of order");
    write_units_before(unit);
    deliver(std::move(b));
}

void RankMergeSink::finish() {
    write_units_before(units_);
    out_.finish();
}

}  // namespace meshless
