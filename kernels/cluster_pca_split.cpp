#include "kernels/cluster_pca_split.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <vector>

#include "kernels/fixed_chunks.hpp"

namespace meshless {

ClusterSplitPlane pca_split_plane(std::span<const Vec3> pos, std::span<const double> value,
                                  std::span<const std::uint32_t> idx, const Vec3& centre, double mean_value,
                                  double pos_scale, double value_scale) {
    using Sums = std::array<double, 10>;  // upper triangle of the 4x4 covariance
    const Sums total = chunks::reduce(
        idx.size(), Sums{},
        [&](std::size_t b, std::size_t e) {
            Sums s{};
            for (std::size_t i = b; i < e; ++i) {
                const std::uint32_t j = idx[i];
                const double v0 = (pos[j].x - centre.x) * pos_scale, v1 = (pos[j].y - centre.y) * pos_scale,
                             v2 = (pos[j].z - centre.z) * pos_scale, v3 = (value[j] - mean_value) * value_scale;
                s[0] += v0 * v0; s[1] += v0 * v1; s[2] += v0 * v2; s[3] += v0 * v3;
                s[4] += v1 * v1; s[5] += v1 * v2; s[6] += v1 * v3;
                s[7] += v2 * v2; s[8] += v2 * v3;
                s[9] += v3 * v3;
            }
            return s;
        },
        [](Sums a, const Sums& b) {
            for (int t = 0; t < 10; ++t) a[t] += b[t];
            return a;
        });
    Eigen::Matrix4d cov;
    int t = 0;
    for (int r = 0; r < 4; ++r)
        for (int c = r; c < 4; ++c) cov(r, c) = cov(c, r) = total[t++] / static_cast<double>(idx.size());
    ClusterSplitPlane out;
    if (cov.topLeftCorner<3, 3>().diagonal().sum() <= 0) return out;  // no spatial extent: every split skips
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(cov);
    // eigenvalues ascending: e1 is column 3, e2 column 2
    Eigen::Vector4d e = es.eigenvectors().col(3);
    Vec3 n{e(0), e(1), e(2)};
    if (norm(n) <= 1e-9) {
        e = es.eigenvectors().col(2);
        n = {e(0), e(1), e(2)};
        out.second = true;
    }
    out.normal = normalized(n);
    return out;
}

std::size_t partition_by_plane(std::span<const Vec3> pos, std::span<std::uint32_t> idx, const Vec3& centre,
                               const Vec3& normal) {
    auto behind = [&](std::uint32_t j) { return dot(pos[j] - centre, normal) < 0; };
    const std::size_t n = idx.size();
    if (n < chunks::kParallelItems) {
        auto mid = std::partition(idx.begin(), idx.end(), behind);
        return static_cast<std::size_t>(mid - idx.begin());
    }
    // chunked stable partition: count per chunk, then scatter through a buffer
    const std::size_t c = chunks::count(n);
    std::vector<std::size_t> nb(c);
    chunks::for_each(n, [&](std::size_t k, std::size_t b, std::size_t e) {
        std::size_t m = 0;
        for (std::size_t i = b; i < e; ++i) m += behind(idx[i]) ? 1 : 0;
        nb[k] = m;
    });
    std::vector<std::size_t> front(c), back(c);
    std::size_t total = 0;
    for (std::size_t k = 0; k < c; ++k) {
        front[k] = total;
        total += nb[k];
    }
    std::size_t b2 = total;
    for (std::size_t k = 0; k < c; ++k) {
        back[k] = b2;
        b2 += std::min(n, (k + 1) * chunks::kChunk) - k * chunks::kChunk - nb[k];
    }
    std::vector<std::uint32_t> tmp(n);
    chunks::for_each(n, [&](std::size_t k, std::size_t b, std::size_t e) {
        std::size_t f = front[k], r = back[k];
        for (std::size_t i = b; i < e; ++i) {
            const std::uint32_t j = idx[i];
            if (behind(j)) tmp[f++] = j;
            else tmp[r++] = j;
        }
    });
    chunks::for_each(n, [&](std::size_t, std::size_t b, std::size_t e) { std::copy(tmp.begin() + b, tmp.begin() + e, idx.begin() + b); });
    return total;
}

}  // namespace meshless
