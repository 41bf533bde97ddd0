#include "kernels/point_dedup.hpp"

#include <cmath>
#include <limits>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) {
    // mixes the three cell indices (collisions only cost distance checks)
    std::uint64_t h = static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ULL;
    h ^= static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4FULL + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k) * 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
    return h;
}

}  // namespace

PointDedup::PointDedup(double fraction, double cell) : fraction_(fraction), cell_(cell) {
    if (!(fraction >= 0) || !std::isfinite(fraction)) throw InvalidArgument("dedup: the fraction must be finite and >= 0");
    if (!(cell > 0) || !std::isfinite(cell)) throw InvalidArgument("dedup: the hash cell must be finite and > 0");
}

bool PointDedup::keep(const Vec3& p, double radius) {
    const double d = fraction_ * radius;
    const std::int64_t ci = static_cast<std::int64_t>(std::floor(p.x / cell_));
    const std::int64_t cj = static_cast<std::int64_t>(std::floor(p.y / cell_));
    const std::int64_t ck = static_cast<std::int64_t>(std::floor(p.z / cell_));
    if (d > 0 && std::isfinite(d)) {
        const double d2 = d * d;
        const double span = 2 * std::ceil(d / cell_) + 1;
        if (span * span * span > double(pts_.size())) {
            // a search box of more cells than kept points: look at every kept point
            for (const Vec3& q : pts_) {
                const Vec3 e = q - p;
                if (dot(e, e) < d2) {
                    ++removed_;
                    return false;
                }
            }
        } else {
            const auto r = static_cast<std::int64_t>(std::ceil(d / cell_));
            for (std::int64_t k = ck - r; k <= ck + r; ++k)
                for (std::int64_t j = cj - r; j <= cj + r; ++j)
                    for (std::int64_t i = ci - r; i <= ci + r; ++i) {
                        const auto it = head_.find(key(i, j, k));
                        if (it == head_.end()) continue;
                        for (std::uint32_t q = it->second; q != kNone; q = next_[q]) {
                            const Vec3 e = pts_[q] - p;
                            if (dot(e, e) < d2) {
                                ++removed_;
                                return false;
                            }
                        }
                    }
        }
    }
    const auto idx = static_cast<std::uint32_t>(pts_.size());
    pts_.push_back(p);
    auto [it, fresh] = head_.try_emplace(key(ci, cj, ck), idx);
    next_.push_back(fresh ? kNone : it->second);
    if (!fresh) it->second = idx;
    return true;
}

}  // namespace meshless
