#include "kernels/point_set.hpp"
#include "kernels/merge_near_duplicates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace meshless {
namespace {

struct CellKey {
    std::int64_t x, y, z;
    bool operator==(const CellKey&) const = default;
};
struct CellKeyHash {
    std::size_t operator()(const CellKey& k) const {
        std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull;
        h ^= static_cast<std::uint64_t>(k.y) + 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
        h ^= static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};

std::array<Vec3, 2> bbox(std::span<const Vec3> pos) { return bounding_box(pos); }

}  // namespace

double mean_point_spacing(std::span<const Vec3> pos) {
    if (pos.size() < 2) return 0;
    return mean_point_spacing(bbox(pos), pos.size());
}

double mean_point_spacing(const std::array<Vec3, 2>& box, std::uint64_t n) {
    if (n < 2) return 0;
    const Vec3 w = box[1] - box[0];
    const double wmax = std::max({w.x, w.y, w.z});
    if (!(wmax > 0)) return 0;
    double prod = 1;
    int k = 0;
    for (int a = 0; a < 3; ++a)
        if (w[a] > 1e-9 * wmax) { prod *= w[a]; ++k; }
    return std::pow(prod / static_cast<double>(n), 1.0 / k);
}

MergedPoints merge_near_duplicates(std::span<const Vec3> pos, std::span<const double> value, double tolerance) {
    if (pos.empty()) {
        MergedPoints out;
        out.tolerance = std::max(0.0, tolerance);
        return out;
    }
    return merge_near_duplicates(pos, value, tolerance, bbox(pos), pos.size());
}

MergedPoints merge_near_duplicates(std::span<const Vec3> pos, std::span<const double> value, double tolerance,
                                   const std::array<Vec3, 2>& frame, std::uint64_t frame_points) {
    MergedPoints out;
    out.tolerance = std::max(0.0, tolerance);
    if (pos.empty()) return out;
    const auto [lo, hi] = frame;
    out.origin = (lo + hi) * 0.5;
    const Vec3 w = hi - lo;
    const double wmax = std::max({w.x, w.y, w.z});
    const double tol = out.tolerance;
    double cell = tol > 0 ? 4 * tol : std::max(mean_point_spacing(frame, frame_points), 0.0);
    cell = std::max(cell, wmax * 1e-15);
    // (subnormal cells: 1 / cell would overflow and a cell index be NaN; a cell of at least 4 x the
    // smallest normal double keeps 1 / cell finite, and a larger cell only widens the search)
    cell = std::max(cell, 4 * std::numeric_limits<double>::min());
    if (!(cell > 0) || !std::isfinite(cell)) cell = 1;  // all points coincide
    const double inv = 1.0 / cell;

    std::unordered_map<CellKey, std::uint32_t, CellKeyHash> head;
    head.reserve(pos.size());
    std::vector<std::uint32_t> next;     // chain of kept points within a hash cell
    std::vector<double> sum;
    std::vector<std::uint32_t> cnt;
    out.pos.reserve(pos.size());
    constexpr std::uint32_t none = 0xFFFFFFFFu;
    const double tol2 = tol * tol;

    for (std::size_t i = 0; i < pos.size(); ++i) {
        const Vec3 r = pos[i] - out.origin;
        const double u[3] = {(r.x - (lo.x - out.origin.x)) * inv, (r.y - (lo.y - out.origin.y)) * inv,
                             (r.z - (lo.z - out.origin.z)) * inv};
        std::int64_t c[3];
        int from[3], to[3];
        for (int a = 0; a < 3; ++a) {
            const double f = std::floor(u[a]);
            c[a] = static_cast<std::int64_t>(f);
            const double frac = (u[a] - f) * cell;  // distance to the lower face
            from[a] = frac <= tol ? -1 : 0;
            to[a] = cell - frac <= tol ? 1 : 0;
        }
        std::uint32_t found = none;
        for (int dz = from[2]; dz <= to[2] && found == none; ++dz)
            for (int dy = from[1]; dy <= to[1] && found == none; ++dy)
                for (int dx = from[0]; dx <= to[0] && found == none; ++dx) {
                    const auto it = head.find(CellKey{c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == head.end()) continue;
                    for (std::uint32_t k = it->second; k != none; k = next[k]) {
                        const Vec3 d = out.pos[k] - r;
                        if (dot(d, d) <= tol2) { found = k; break; }
                    }
                }
        if (found != none) {
            sum[found] += value[i];
            ++cnt[found];
            ++out.merged;
            continue;
        }
        const auto k = static_cast<std::uint32_t>(out.pos.size());
        out.pos.push_back(r);
        sum.push_back(value[i]);
        cnt.push_back(1);
        auto [it, inserted] = head.try_emplace(CellKey{c[0], c[1], c[2]}, k);
        next.push_back(inserted ? none : it->second);
        if (!inserted) it->second = k;
    }
    out.value.resize(out.pos.size());
    for (std::size_t k = 0; k < out.pos.size(); ++k) out.value[k] = cnt[k] == 1 ? sum[k] : sum[k] / cnt[k];
    out.pos.shrink_to_fit();
    return out;
}

}  // namespace meshless
