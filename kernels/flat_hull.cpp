#include "kernels/flat_hull.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace meshless {

bool FlatHull::off(const Vec3& p) const {
    double off2 = 0;
    for (int a = 0; a < nacross; ++a) {
        const double d = dot(p - o, across[a]);
        off2 += d * d;
    }
    const double tol = 1e-4 * spread;
    return off2 > tol * tol;
}

std::optional<FlatHull> flat_hull(const PointMoments& m) {
    if (m.count < 2) return std::nullopt;
    const double n = m.count;
    const Eigen::Vector3d mean(m.sum[0] / n, m.sum[1] / n, m.sum[2] / n);
    Eigen::Matrix3d sq;
    sq << m.sq[0], m.sq[1], m.sq[2], m.sq[1], m.sq[3], m.sq[4], m.sq[2], m.sq[4], m.sq[5];
    const Eigen::Matrix3d cov = sq / n - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d lam = es.eigenvalues();  // ascending
    if (!(lam(2) > 0) || lam(0) > 1e-12 * lam(2)) return std::nullopt;
    FlatHull h;
    h.nacross = lam(1) > 1e-12 * lam(2) ? 1 : 2;
    for (int q = 0; q < h.nacross; ++q) h.across[q] = Vec3{es.eigenvectors()(0, q), es.eigenvectors()(1, q), es.eigenvectors()(2, q)};
    h.o = Vec3{m.ref.x + mean(0), m.ref.y + mean(1), m.ref.z + mean(2)};
    h.spread = std::sqrt(lam(2));
    return h;
}

bool all_flat(std::span<const Vec3> pts) {
    if (pts.empty()) return false;
    PointMoments all;
    all.ref = pts.front();  // (a data point: exact zeros along a plane of the data)
    for (const Vec3& p : pts) all.add(p - all.ref);
    return flat_hull(all).has_value();
}

}  // namespace meshless
