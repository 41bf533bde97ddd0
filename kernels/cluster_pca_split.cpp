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
    // chunked, in place: each chunk partitioned by std::partition (in parallel), then neighbouring
    // runs merged pairwise, [L1 R1][L2 R2] -> [L1 L2 R1 R2] by one rotate, in a fixed tree order
    const std::size_t c = chunks::count(n);
    struct Run {
        std::size_t begin, end, behind;  // [begin, begin + behind) behind the plane
    };
    std::vector<Run> runs(c);
    chunks::for_each(n, [&](std::size_t k, std::size_t b, std::size_t e) {
        auto mid = std::partition(idx.begin() + static_cast<std::ptrdiff_t>(b), idx.begin() + static_cast<std::ptrdiff_t>(e), behind);
        runs[k] = {b, e, static_cast<std::size_t>(mid - idx.begin()) - b};
    });
    while (runs.size() > 1) {
        std::vector<Run> next((runs.size() + 1) / 2);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, next.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t q = r.begin(); q != r.end(); ++q) {
                if (2 * q + 1 == runs.size()) {
                    next[q] = runs[2 * q];
                    continue;
                }
                const Run& x = runs[2 * q];
                const Run& y = runs[2 * q + 1];
                std::rotate(idx.begin() + static_cast<std::ptrdiff_t>(x.begin + x.behind),
                            idx.begin() + static_cast<std::ptrdiff_t>(y.begin),
                            idx.begin() + static_cast<std::ptrdiff_t>(y.begin + y.behind));
                next[q] = {x.begin, y.end, x.behind + y.behind};
            }
        });
        runs.swap(next);
    }
    const std::size_t total = runs[0].behind;
    return total;
}

}  // namespace meshless
