#include "stream/stream_endpoints.hpp"

#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
template <class T>
std::vector<T> take_spare(std::vector<std::vector<T>>& spare) {
    std::vector<T> v;
    if (!spare.empty()) {
        v.swap(spare.back());
        spare.pop_back();
    }
    return v;
}
}  // namespace

std::optional<Batch> StreamSource::next() {
    Batch b;
    b.seq = seq_;
    b.kind = r_.kind();
    {
        std::lock_guard lock(m_);
        // both kinds: a stage downstream may turn the samples into points in the same batch
        b.samples = take_spare(spare_samples_);
        b.points = take_spare(spare_points_);
    }
    auto n = r_.next_records([&](std::uint64_t count) -> void* {
        if (b.kind == RecordKind::sample) {
            b.samples.resize(count);
            return b.samples.data();
        }
        b.points.resize(count);
        return b.points.data();
    });
    if (!n) return std::nullopt;
    ++seq_;
    return b;
}

bool StreamSource::recycle(Batch& consumed) {
    constexpr std::size_t kKeep = 8;
    std::lock_guard lock(m_);
    if (consumed.points.capacity() != 0 && spare_points_.size() < kKeep) {
        consumed.points.clear();
        spare_points_.push_back(std::move(consumed.points));
    }
    if (consumed.samples.capacity() != 0 && spare_samples_.size() < kKeep) {
        consumed.samples.clear();
        spare_samples_.push_back(std::move(consumed.samples));
    }
    return true;
}

StreamSink::StreamSink(std::FILE* f, std::string name, RecordKind kind, const StreamMeta& meta, bool compress)
    : w_(f, std::move(name), kind, compress), kind_(kind) {
    w_.write_meta(meta);
}

void StreamSink::consume(Batch&& b) {
    if (b.kind != kind_)
        throw FormatError(std::string("stream writer: got ") + (b.kind == RecordKind::point ? "points" : "samples") +
                          ", expected " + (kind_ == RecordKind::point ? "points" : "samples"));
    if (b.kind == RecordKind::sample) w_.write_data(b.seq, b.samples.data(), b.samples.size());
    else w_.write_data(b.seq, b.points.data(), b.points.size());
}

}  // namespace meshless
