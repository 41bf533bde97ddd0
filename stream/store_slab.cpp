#include "stream/store_slab.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

#include "stream/seconds_since.hpp"

namespace meshless {

namespace {
constexpr double kNoBound = std::numeric_limits<double>::infinity();
}  // namespace

StoreBrickIndex::StoreBrickIndex(const PointStore& store) : bricks_(store.bricks()) {
    const PointStoreInfo& in = store.info();
    lo_ = Vec3{in.lo[0], in.lo[1], in.lo[2]};
    const Vec3 hi{in.hi[0], in.hi[1], in.hi[2]};
    side_ = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::cbrt(static_cast<double>(bricks_.size()))), 1, 64);
    for (int a = 0; a < 3; ++a) inv_[a] = hi[a] > lo_[a] ? static_cast<double>(side_) / (hi[a] - lo_[a]) : 0.0;
    std::vector<std::vector<std::uint32_t>> lists(static_cast<std::size_t>(side_ * side_ * side_));
    for (std::size_t i = 0; i < bricks_.size(); ++i) {
        const auto r = cells(Vec3{bricks_[i].lo[0], bricks_[i].lo[1], bricks_[i].lo[2]}, Vec3{bricks_[i].hi[0], bricks_[i].hi[1], bricks_[i].hi[2]});
        for (std::int64_t k = r[0][2]; k <= r[1][2]; ++k)
            for (std::int64_t j = r[0][1]; j <= r[1][1]; ++j)
                for (std::int64_t c = r[0][0]; c <= r[1][0]; ++c) lists[static_cast<std::size_t>(c + side_ * (j + side_ * k))].push_back(static_cast<std::uint32_t>(i));
    }
    first_.push_back(0);
    for (const auto& l : lists) {
        list_.insert(list_.end(), l.begin(), l.end());
        first_.push_back(list_.size());
    }
    stamp_.assign(bricks_.size(), 0);
}

bool StoreBrickIndex::ball_meets(const PointBrickEntry& b, const Vec3& c, double r) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
        const auto ua = static_cast<std::size_t>(a);
        const double e = c[a] < b.lo[ua] ? b.lo[ua] - c[a] : (c[a] > b.hi[ua] ? c[a] - b.hi[ua] : 0.0);
        d2 += e * e;
    }
    return d2 <= r * r;
}

std::array<std::array<std::int64_t, 3>, 2> StoreBrickIndex::cells(const Vec3& lo, const Vec3& hi) const {
    std::array<std::array<std::int64_t, 3>, 2> r{};
    for (int a = 0; a < 3; ++a) {
        const double top = static_cast<double>(side_ - 1);
        const auto ua = static_cast<std::size_t>(a);
        r[0][ua] = static_cast<std::int64_t>(std::clamp(std::floor((lo[a] - lo_[a]) * inv_[a]), 0.0, top));
        r[1][ua] = static_cast<std::int64_t>(std::clamp(std::floor((hi[a] - lo_[a]) * inv_[a]), 0.0, top));
    }
    return r;
}

StoreSlab store_slab(const PointStore& store, const ScatteredStorePlan& plan, const std::array<double, 2>& query, double halo,
                     const std::vector<char>& extra) {
    const BinningGrid& g = plan.grid;
    StoreSlab s;
    s.query = query;
    s.loaded = {s.query[0] - halo, s.query[1] + halo};
    if (s.loaded[0] <= plan.frame.bounds[0].z) s.loaded[0] = -kNoBound;  // (no points beyond the data)
    if (s.loaded[1] >= plan.frame.bounds[1].z) s.loaded[1] = kNoBound;
    const auto& bricks = store.bricks();
    s.in.assign(bricks.size(), 0);
    std::uint64_t read = 0, whole = 0;
    for (std::size_t i = 0; i < bricks.size(); ++i) {
        s.in[i] = extra[i] ? 2 : !(bricks[i].hi[2] < s.loaded[0] || bricks[i].lo[2] > s.loaded[1]);
        if (s.in[i]) read += bricks[i].count;
        if (s.in[i] == 2) whole += bricks[i].count;
    }
    // the cell layers meeting the loaded range bound the points kept of the bricks read
    std::uint64_t layers = 0;
    for (std::int64_t k = 0; k < g.dims[2]; ++k) {
        const double z0 = g.origin.z + static_cast<double>(k) * g.cell.z;
        if (!(z0 + g.cell.z < s.loaded[0] || z0 > s.loaded[1])) layers += plan.layer_points[static_cast<std::size_t>(k)];
    }
    s.points = std::min(read, layers + whole);
    return s;
}

PointSet load_store_slab(const PointStore& store, const StoreSlab& slab, double& seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    PointSet ps;
    ps.pos.reserve(slab.points);
    ps.value.reserve(slab.points);
    std::vector<double> raw;
    for (std::size_t i = 0; i < slab.in.size(); ++i) {
        if (!slab.in[i]) continue;
        store.read_brick(i, raw);
        const bool all = slab.in[i] == 2;
        for (std::size_t k = 0; k < raw.size(); k += 4) {
            if (!all && !(raw[k + 2] >= slab.loaded[0] && raw[k + 2] <= slab.loaded[1])) continue;
            ps.pos.push_back(Vec3{raw[k], raw[k + 1], raw[k + 2]});
            ps.value.push_back(raw[k + 3]);
        }
    }
    ps.value_name = store.info().value_name;
    ps.has_values = store.info().has_values;
    ps.blocks.push_back(PointSetBlock{std::filesystem::path(store.path()).filename().string(),
                                      {static_cast<std::int64_t>(ps.pos.size()), 1, 1}, 0, ps.pos.size()});
    seconds += seconds_since(t0);
    return ps;
}

double store_first_halo(const ScatteredStorePlan& plan, const FieldParams& field_params) {
    const BinningGrid& g = plan.grid;
    const Vec3 ext = plan.frame.bounds[1] - plan.frame.bounds[0];
    const double volume = std::max(ext.x, g.cell.x) * std::max(ext.y, g.cell.y) * std::max(ext.z, g.cell.z);
    const double leaf = std::cbrt(3.0 * field_params.mpu_max_points * volume / (4.0 * std::numbers::pi * static_cast<double>(plan.frame.points)));
    return std::max(2 * g.cell.z, 2 * leaf);
}

StoreSlabRegion::StoreSlabRegion(const PointStore& store, const ScatteredStorePlan& plan, const StoreBrickIndex& index,
                                 const StoreSlab& slab, const std::array<Vec3, 2>& query_xy) {
    region.frame = plan.frame;
    region.query = {Vec3{query_xy[0].x, query_xy[0].y, slab.query[0]}, Vec3{query_xy[1].x, query_xy[1].y, slab.query[1]}};
    region.loaded = {Vec3{-kNoBound, -kNoBound, slab.loaded[0]}, Vec3{kNoBound, kNoBound, slab.loaded[1]}};
    region.missing = [this, &store, &plan, &index, &slab](const Vec3& c, double r) {
        const std::lock_guard<std::mutex> hold(lock_);
        // the bricks meeting the ball that were not read, or read in part where the ball
        // leaves the loaded range; or the grid cells it meets outside that range
        const bool below = c.z - r < slab.loaded[0], above = c.z + r > slab.loaded[1];
        std::uint64_t n = 0;
        index.meeting_ball(c, r, [&](std::size_t i) {
            const PointBrickEntry& b = store.bricks()[i];
            if (slab.in[i] == 0 || (slab.in[i] == 1 && ((below && b.lo[2] < slab.loaded[0]) || (above && b.hi[2] > slab.loaded[1]))))
                n += b.count;
        });
        return std::min(n, plan.points_near(c, r, slab.loaded));
    };
    region.present = [&plan](const Vec3& c, double r) { return plan.points_surely_in(c, r); };
}

std::size_t add_lacking_bricks(const MpuField& field, const StoreBrickIndex& index, std::vector<char>& extra,
                               std::vector<std::pair<Vec3, double>>& seen) {
    std::size_t added = 0;
    for (const auto& [c, r] : field.lacking_balls()) index.meeting_ball(c, r, [&](std::size_t i) { added += !extra[i]; extra[i] = 1; });
    seen.insert(seen.end(), field.lacking_balls().begin(), field.lacking_balls().end());
    return added;
}

std::vector<char> bricks_still_lacking(const PointStore& store, const StoreBrickIndex& index, std::vector<std::pair<Vec3, double>>& seen,
                                       double from) {
    std::vector<char> extra(store.bricks().size(), 0);
    std::erase_if(seen, [&](const std::pair<Vec3, double>& b) { return b.first.z + b.second < from; });
    for (const auto& [c, r] : seen)
        index.meeting_ball(c, r, [&](std::size_t i) { extra[i] = extra[i] || store.bricks()[i].hi[2] >= from; });
    return extra;
}

void add_slab_field_stats(FieldBuildStats& to, const FieldBuildStats& s) {
    to.locals += s.locals;
    to.interpolated += s.interpolated;
    to.regularised += s.regularised;
    to.linear_fallback += s.linear_fallback;
    to.polynomial_only += s.polynomial_only;
    to.capped += s.capped;
    to.grown += s.grown;
    to.spanned += s.spanned;
    to.memory_bytes = std::max(to.memory_bytes, s.memory_bytes);
}

void BatchBuffer::forward(Sink& sink, std::uint64_t& seq) {
    for (Batch& b : batches) {
        b.seq = seq++;
        sink.consume(std::move(b));
    }
    batches.clear();
}

}  // namespace meshless
