#include "stream/stream_endpoints.hpp"

#include <cstdint>
#include <cstring>
#include <string>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
/// The index of the first record of `n` (each `per` float32s) with a NaN or infinite float, or n.
/// One pass over the bits (exponent all ones), vectorised: memory speed on the pipe's serial path.
std::size_t first_non_finite(const void* records, std::size_t n, std::size_t per) {
    const auto* u = static_cast<const std::uint32_t*>(records);
    const std::size_t words = n * per;
    std::uint32_t bad = 0;
    for (std::size_t i = 0; i < words; ++i) bad |= ((u[i] & 0x7f800000u) == 0x7f800000u);
    if (!bad) return n;
    for (std::size_t i = 0; i < words; ++i)
        if ((u[i] & 0x7f800000u) == 0x7f800000u) return i / per;
    return n;
}

/// Points and samples with a NaN/Inf field are refused: meshless never writes one (Newton drops
/// non-finite points, generate skips cells with a non-finite corner), so the stream is damaged or
/// foreign, and a PLY, VTP or picture of it would hold nothing usable.
template <class R>
void check_finite(const std::vector<R>& records, const std::string& name, std::uint64_t before, const char* what) {
    static_assert(sizeof(R) % sizeof(float) == 0);
    const std::size_t at = first_non_finite(records.data(), records.size(), sizeof(R) / sizeof(float));
    if (at < records.size())
        throw FormatError(name + ": " + what + " record " + std::to_string(before + at) +
                          " holds a NaN or infinite number (meshless writes none: a damaged or foreign stream)");
}

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
    // spare sample arrays keep their size (records are read over them: resizing to a frame's count
    // then zero-fills nothing, or only what grew)
    if (b.kind != RecordKind::sample) b.samples.clear();
    const bool blocks = r_.has_blocks();
    auto n = r_.next_records([&](std::uint64_t count) -> void* {
        if (blocks) {
            packed_.resize(static_cast<std::size_t>(count) * kPointBlockRecordSize);
            return packed_.data();
        }
        if (b.kind == RecordKind::seed) {
            b.seeds.resize(count);
            return b.seeds.data();
        }
        if (b.kind == RecordKind::sample) {
            if (count > b.samples.capacity()) b.samples.clear();  // growing copies nothing old
            b.samples.resize(count);
            return b.samples.data();
        }
        b.points.resize(count);
        return b.points.data();
    });
    if (!n) return std::nullopt;
    if (blocks) deinterleave_point_blocks(packed_.data(), static_cast<std::size_t>(*n), b.points, b.point_block);
    if (b.kind == RecordKind::point) check_finite(b.points, r_.name(), records_, "point");
    if (b.kind == RecordKind::sample) check_finite(b.samples, r_.name(), records_, "sample");
    records_ += *n;
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
        spare_samples_.push_back(std::move(consumed.samples));
    }
    return true;
}

StreamSink::StreamSink(std::FILE* f, std::string name, RecordKind kind, const StreamMeta& meta, bool compress,
                       bool with_blocks)
    : w_(f, std::move(name), kind, compress, with_blocks ? kStreamFlagBlocks : 0), kind_(kind), blocks_(with_blocks) {
    w_.write_meta(meta);
}


void StreamSink::consume(Batch&& b) {
    if (b.kind == RecordKind::sample) {
        w_.write_data(b.seq, b.samples.data(), b.samples.size());
    } else if (b.kind == RecordKind::seed) {
        w_.write_data(b.seq, b.seeds.data(), b.seeds.size());
    } else if (blocks_) {
        if (b.point_block.size() != b.points.size())
            throw FormatError("stream writer: a batch of " + std::to_string(b.points.size()) + " points has " +
                              std::to_string(b.point_block.size()) + " block ids");
        interleave_point_blocks(b.points.data(), b.point_block.data(), b.points.size(), packed_);
        w_.write_data(b.seq, packed_.data(), b.points.size());
    } else {
        w_.write_data(b.seq, b.points.data(), b.points.size());
    }
}

}  // namespace meshless
