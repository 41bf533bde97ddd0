#include "kernels/point_coverage.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

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

}  // namespace

struct PointCoverage::Impl {
    Cloud cloud;
    std::unique_ptr<Tree> tree;
    std::vector<double> reach2;  ///< (factor * h_i)^2
};

PointCoverage::PointCoverage(std::span<const Vec3> points, double factor) : impl_(std::make_unique<Impl>()) {
    impl_->cloud.pts.assign(points.begin(), points.end());
    const std::size_t n = impl_->cloud.pts.size();
    if (n == 0) return;
    impl_->tree = std::make_unique<Tree>(3, impl_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    impl_->tree->buildIndex();
    const std::size_t k = std::min<std::size_t>(9, n);  // the point itself + 8 neighbours
    std::vector<unsigned> idx(k);
    std::vector<double> d2(k);
    impl_->reach2.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = impl_->cloud.pts[i];
        const double q[3] = {p.x, p.y, p.z};
        const std::size_t got = impl_->tree->knnSearch(q, k, idx.data(), d2.data());
        const double h = got > 1 ? std::sqrt(d2[got - 1]) : 0.0;
        impl_->reach2[i] = (factor * h) * (factor * h);
    }
}

PointCoverage::~PointCoverage() = default;

bool PointCoverage::covered(const Vec3& x) const {
    if (!impl_->tree) return false;
    const double q[3] = {x.x, x.y, x.z};
    unsigned i = 0;
    double d2 = std::numeric_limits<double>::infinity();
    impl_->tree->knnSearch(q, 1, &i, &d2);
    return d2 <= impl_->reach2[i];
}

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

}  // namespace meshless
