#include "stream/stream_endpoints.hpp"

#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

std::optional<Batch> StreamSource::next() {
    buf_.clear();
    auto n = r_.next_data(buf_);
    if (!n) return std::nullopt;
    Batch b;
    b.seq = seq_++;
    b.kind = r_.kind();
    if (b.kind == RecordKind::sample) {
        b.samples.resize(*n);
        std::memcpy(b.samples.data(), buf_.data(), buf_.size());
    } else {
        b.points.resize(*n);
        std::memcpy(b.points.data(), buf_.data(), buf_.size());
    }
    return b;
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
