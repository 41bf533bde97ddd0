#include "kernels/point_coverage.hpp"

#include <nanoflann.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <optional>
#include <cmath>
#include <limits>
#include <string>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

struct Cloud {
    std::vector<Vec3> pts;
    std::size_t kdtree_get_point_count() const { return pts.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t d) const { return pts[i][static_cast<int>(d)]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const { return false; }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3>;

constexpr std::size_t kSpacingNeighbours = 8;   ///< h_i: distance to the 8th neighbour
constexpr std::size_t kSurroundNeighbours = 12; ///< K of test (b)
constexpr double kSurroundMaxMean = 0.5;        ///< |mean unit vector| of a surrounded position
constexpr double kSurroundReach = 1.5;          ///< test (b) reaches 1.5 x factor x mean(h)

}  // namespace

struct PointCoverage::Impl {
    Cloud cloud;
    std::unique_ptr<Tree> tree;
    std::vector<double> reach;  ///< factor * h_i
    std::vector<double> values; ///< empty: no range, no nearest values
    double global_lo = 0, global_hi = 0;
    double factor = 1;
    std::optional<std::array<Vec3, 2>> held;     ///< a part of a whole set: the box whose points were given
    mutable std::atomic<bool> inexact{false};    ///< a query read a neighbourhood reaching beyond `held`

    // Notes a neighbourhood a query read: the ball (c, r) must lie inside the given points' box.
    void note(const Vec3& c, double r) const {
        if (!held) return;
        const auto& [lo, hi] = *held;
        if (!(c.x - r >= lo.x && c.x + r <= hi.x && c.y - r >= lo.y && c.y + r <= hi.y && c.z - r >= lo.z && c.z + r <= hi.z))
            inexact.store(true, std::memory_order_relaxed);
    }
    // the ball of point i's spacing neighbours (reach / factor, rounded up)
    void note_point(std::size_t i) const { note(cloud.pts[i], reach[i] / factor * (1 + 1e-9)); }

    void build(double f) {
        factor = f;
        const std::size_t n = cloud.pts.size();
        if (n == 0) return;
        tree = std::make_unique<Tree>(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
        tree->buildIndex();
        const std::size_t k = std::min<std::size_t>(kSpacingNeighbours + 1, n);  // the point itself + 8
        reach.resize(n);
        // each reach is its own query: on every core (the same values for any thread count), the
        // points taken in the tree's leaf order (vAcc) so that consecutive queries walk the same
        // nodes (1 M points in random order, 2 threads: 3.9 -> 1.1 s)
        const auto& order = tree->vAcc;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
            std::array<unsigned, kSpacingNeighbours + 1> idx{};
            std::array<double, kSpacingNeighbours + 1> d2{};
            for (std::size_t j = r.begin(); j != r.end(); ++j) {
                const std::size_t i = order[j];
                const Vec3& p = cloud.pts[i];
                const double q[3] = {p.x, p.y, p.z};
                const std::size_t got = tree->knnSearch(q, k, idx.data(), d2.data());
                reach[i] = factor * (got > 1 ? std::sqrt(d2[got - 1]) : 0.0);
            }
        });
    }

    bool covered(const Vec3& x) const {
        if (!tree) return false;
        const double q[3] = {x.x, x.y, x.z};
        {  // (a) from the nearest point alone, the common case (a position near the data)
            unsigned i0 = 0;
            double d20 = 0;
            if (tree->knnSearch(q, 1, &i0, &d20) == 0) return false;
            note(x, std::sqrt(d20) * (1 + 1e-9));
            note_point(i0);
            if (std::sqrt(d20) <= reach[i0]) return true;
        }
        std::array<unsigned, kSurroundNeighbours> idx{};
        std::array<double, kSurroundNeighbours> d2{};
        const std::size_t got = tree->knnSearch(q, std::min(kSurroundNeighbours, cloud.pts.size()), idx.data(), d2.data());
        if (got == 0) return false;
        note(x, std::sqrt(d2[got - 1]) * (1 + 1e-9));
        for (std::size_t j = 0; j < got; ++j) note_point(idx[j]);
        const double d0 = std::sqrt(d2[0]);
        if (d0 <= reach[idx[0]]) return true;  // (a) (the same point: nanoflann's 1-NN and 12-NN searches agree on it)
        if (got < 4) return false;
        double mean_reach = 0;
        Vec3 m{0, 0, 0};
        for (std::size_t j = 0; j < got; ++j) {
            mean_reach += reach[idx[j]];
            const Vec3 v = cloud.pts[idx[j]] - x;
            const double len = std::sqrt(d2[j]);
            if (len > 0) m = m + v * (1.0 / len);
        }
        mean_reach /= static_cast<double>(got);
        if (d0 > kSurroundReach * mean_reach) return false;
        m = m * (1.0 / static_cast<double>(got));
        return std::sqrt(m.x * m.x + m.y * m.y + m.z * m.z) <= kSurroundMaxMean;  // (b)
    }

    double nearest_value(const Vec3& x) const {
        const double q[3] = {x.x, x.y, x.z};
        unsigned i = 0;
        double d2 = 0;
        return tree->knnSearch(q, 1, &i, &d2) ? values[i] : std::numeric_limits<double>::quiet_NaN();
    }
};

PointCoverage::PointCoverage(std::span<const Vec3> points, double factor) : impl_(std::make_unique<Impl>()) {
    impl_->cloud.pts.assign(points.begin(), points.end());
    impl_->build(factor);
}

PointCoverage::PointCoverage(std::span<const Vec3> points, std::span<const double> values, double factor)
    : impl_(std::make_unique<Impl>()) {
    if (values.size() != points.size())
        throw InvalidArgument("PointCoverage: " + std::to_string(values.size()) + " values for " +
                              std::to_string(points.size()) + " points");
    impl_->cloud.pts.assign(points.begin(), points.end());
    impl_->values.assign(values.begin(), values.end());
    if (!values.empty()) {
        const auto [mn, mx] = std::minmax_element(values.begin(), values.end());
        impl_->global_lo = *mn;
        impl_->global_hi = *mx;
    }
    impl_->build(factor);
}

PointCoverage::~PointCoverage() = default;

void PointCoverage::set_part_of(const std::array<Vec3, 2>& held) {
    impl_->held = held;
    impl_->inexact.store(false);
}

bool PointCoverage::part_exact() const { return !impl_->inexact.load(); }

void PointCoverage::set_value_range(const std::array<double, 2>& range) {
    if (impl_->values.empty()) return;
    impl_->global_lo = range[0];
    impl_->global_hi = range[1];
}

bool PointCoverage::covered(const Vec3& x) const { return impl_->covered(x); }

std::size_t PointCoverage::mask(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const {
    std::size_t masked = 0;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (covered(p[i])) continue;
        value[i] = nan;
        if (!grad.empty()) grad[i] = {nan, nan, nan};
        ++masked;
    }
    return masked;
}

SupportCounts PointCoverage::apply(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad,
                                   Extrapolate mode) const {
    SupportCounts c;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const bool with_values = !impl_->values.empty() && impl_->tree;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const bool in = covered(p[i]);
        if (!in) ++c.uncovered;
        if (!in && (mode == Extrapolate::nan || !with_values)) {
            value[i] = nan;
            if (!grad.empty()) grad[i] = {nan, nan, nan};
            continue;
        }
        if (!with_values) continue;
        if (!in && (mode == Extrapolate::nearest || std::isnan(value[i]))) {  // clamp: a field undefined here
            value[i] = impl_->nearest_value(p[i]);
            if (!grad.empty()) grad[i] = {0, 0, 0};
            continue;
        }
        const double v = value[i];
        const double kept = std::isnan(v) ? v : std::clamp(v, impl_->global_lo, impl_->global_hi);
        if (kept != v) {
            value[i] = kept;
            if (!grad.empty()) grad[i] = {0, 0, 0};
            ++c.clamped;
        }
    }
    return c;
}

}  // namespace meshless
