#include "stream/field_query_sources.hpp"

#include <algorithm>

namespace meshless {

namespace {
Batch query_batch(std::uint64_t seq, bool want_grad) {
    Batch b;
    b.seq = seq;
    b.kind = RecordKind::query;
    b.query.want_grad = want_grad;
    return b;
}
}  // namespace

QueryListSource::QueryListSource(std::vector<Vec3> at, bool want_grad, std::size_t batch_queries)
    : at_(std::move(at)), want_grad_(want_grad), per_(batch_queries ? batch_queries : 1) {}

std::optional<Batch> QueryListSource::next() {
    if (next_ >= at_.size()) return std::nullopt;
    Batch b = query_batch(seq_++, want_grad_);
    const std::size_t end = std::min(at_.size(), next_ + per_);
    b.query.at.assign(at_.begin() + static_cast<std::ptrdiff_t>(next_), at_.begin() + static_cast<std::ptrdiff_t>(end));
    next_ = end;
    return b;
}

Vec3 PlaneRaster::position(int row, int col) const {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int ua = std::min(u, v), va = std::max(u, v);
    double q[3];
    q[axis] = at;
    q[ua] = lo_u + (col + 0.5) * pixel;
    q[va] = lo_v + (height - 1 - row + 0.5) * pixel;
    return {q[0], q[1], q[2]};
}

std::optional<Batch> PlaneRasterSource::next() {
    const std::size_t total = static_cast<std::size_t>(r_.width) * static_cast<std::size_t>(r_.height);
    if (next_ >= total) return std::nullopt;
    Batch b = query_batch(seq_++, false);
    const std::size_t end = std::min(total, next_ + per_);
    b.query.at.reserve(end - next_);
    for (std::size_t n = next_; n < end; ++n)
        b.query.at.push_back(r_.position(static_cast<int>(n / static_cast<std::size_t>(r_.width)),
                                         static_cast<int>(n % static_cast<std::size_t>(r_.width))));
    next_ = end;
    return b;
}

std::optional<Batch> GridRasterSource::next() {
    const std::int64_t total = end_;
    if (next_ >= total) return std::nullopt;
    Batch b = query_batch(seq_++, false);
    const std::int64_t end = std::min<std::int64_t>(total, next_ + static_cast<std::int64_t>(per_));
    b.query.at.reserve(static_cast<std::size_t>(end - next_));
    const std::int64_t nx = g_.dims[0], ny = g_.dims[1];
    for (std::int64_t n = next_; n < end; ++n) {
        const std::int64_t i = n % nx, j = (n / nx) % ny, k = n / (nx * ny);
        b.query.at.push_back({g_.origin[0] + i * g_.spacing[0], g_.origin[1] + j * g_.spacing[1], g_.origin[2] + k * g_.spacing[2]});
    }
    next_ = end;
    return b;
}

}  // namespace meshless
