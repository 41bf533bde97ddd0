#include "kernels/local_spacing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace meshless {

double mean_neighbour_spacing(std::span<const Vec3> pos, std::span<const std::uint32_t> idx) {
    const std::size_t n = idx.size();
    if (n < 2) return 0.0;
    // Structure of arrays (per thread, kept at the largest size seen), so that the distances from
    // one point to all later ones and the minima run packet-wide; a minimum does not depend on the
    // order it is taken in, so the result has the bits of the scalar pair loop.
    thread_local Eigen::ArrayXd x, y, z, best, d2;
    const Eigen::Index m = static_cast<Eigen::Index>(n);
    if (x.size() < m) {
        x.resize(m);
        y.resize(m);
        z.resize(m);
        best.resize(m);
        d2.resize(m);
    }
    for (Eigen::Index k = 0; k < m; ++k) {
        const Vec3& p = pos[idx[static_cast<std::size_t>(k)]];
        x(k) = p.x;
        y(k) = p.y;
        z(k) = p.z;
    }
    best.head(m).setConstant(std::numeric_limits<double>::infinity());
    for (Eigen::Index i = 0; i + 1 < m; ++i) {
        const Eigen::Index len = m - i - 1;
        auto d = d2.head(len);  // |p_j - p_i|^2 for j > i, summed x, y, z as dot(e, e)
        d = (x.segment(i + 1, len) - x(i)).square() + (y.segment(i + 1, len) - y(i)).square() +
            (z.segment(i + 1, len) - z(i)).square();
        best(i) = std::min(best(i), d.minCoeff());
        best.segment(i + 1, len) = best.segment(i + 1, len).min(d);
    }
    double sum = 0;
    for (Eigen::Index k = 0; k < m; ++k) sum += std::sqrt(best(k));
    return sum / static_cast<double>(n);
}

}  // namespace meshless
