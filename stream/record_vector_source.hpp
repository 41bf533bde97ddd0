// A Source over records already in memory (seed lists, query points, tests): slices a vector of
// points or samples into batches of at most `batch_records` (<= kMaxBatchRecords) records with
// dense sequence numbers. Batch boundaries depend only on the vector and batch_records, never on the
// thread count. Owns its records (moved in). Not thread-safe (the runner calls next() serially).
#pragma once
#include <algorithm>
#include <vector>

#include "stream/stage.hpp"

namespace meshless {

class RecordVectorSource final : public Source {
public:
    Payload gives() const override { return payload_of(kind_); }
    explicit RecordVectorSource(std::vector<PointRecord> points, std::size_t batch_records = kMaxBatchRecords)
        : kind_(RecordKind::point), points_(std::move(points)), per_(clamp_batch(batch_records)) {}
    explicit RecordVectorSource(std::vector<SampleRecord> samples, std::size_t batch_records = kMaxBatchRecords)
        : kind_(RecordKind::sample), samples_(std::move(samples)), per_(clamp_batch(batch_records)) {}

    std::optional<Batch> next() override {
        const std::size_t total = kind_ == RecordKind::point ? points_.size() : samples_.size();
        if (at_ >= total) return std::nullopt;
        const std::size_t end = std::min(total, at_ + per_);
        Batch b;
        b.seq = seq_++;
        b.kind = kind_;
        if (kind_ == RecordKind::point) b.points.assign(points_.begin() + at_, points_.begin() + end);
        else b.samples.assign(samples_.begin() + at_, samples_.begin() + end);
        at_ = end;
        return b;
    }

private:
    static std::size_t clamp_batch(std::size_t n) { return std::clamp<std::size_t>(n, 1, kMaxBatchRecords); }
    RecordKind kind_;
    std::vector<PointRecord> points_;
    std::vector<SampleRecord> samples_;
    std::size_t per_;
    std::size_t at_ = 0;
    std::uint64_t seq_ = 0;
};

/// A source of no batch that declares `payload`: the run of an empty job (no field, an isovalue outside
/// the data) through the graph its outputs expect, so that they are written empty but valid.
class EmptySource final : public Source {
public:
    explicit EmptySource(Payload payload) : payload_(payload) {}
    std::optional<Batch> next() override { return std::nullopt; }
    Payload gives() const override { return payload_; }

private:
    Payload payload_;
};

}  // namespace meshless
