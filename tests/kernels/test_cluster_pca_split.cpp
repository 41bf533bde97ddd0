// kernels/cluster_pca_split: the PCA plane of a cluster's (x, y, z, f) samples (dissertation section
// 6.3, Figure 6.2) separates two value groups that an axis-aligned split through the centre mixes;
// the second eigenvector is used when the first has no spatial part; the partition does what the
// plane says, the same for the in-place and the chunked (large cluster) paths.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <tbb/global_control.h>

#include "kernels/cluster_pca_split.hpp"

using namespace meshless;

namespace {

struct Cloud {
    std::vector<Vec3> pos;
    std::vector<double> value;
    std::vector<std::uint32_t> idx;
    Vec3 centre;
    double mean = 0;
    void finish() {
        idx.resize(pos.size());
        std::iota(idx.begin(), idx.end(), 0u);
        Vec3 s{};
        for (const Vec3& p : pos) s += p;
        centre = s * (1.0 / pos.size());
        mean = std::accumulate(value.begin(), value.end(), 0.0) / value.size();
    }
};

/// counts of (value 0, value 1) samples on each side
std::array<std::array<int, 2>, 2> sides(const Cloud& c, const Vec3& normal) {
    std::array<std::array<int, 2>, 2> n{};
    for (std::size_t i = 0; i < c.pos.size(); ++i) n[dot(c.pos[i] - c.centre, normal) < 0 ? 0 : 1][c.value[i] > 0.5 ? 1 : 0]++;
    return n;
}

}  // namespace

TEST_CASE("PCA split separates two value groups an axis-aligned split cannot (Figure 6.2)", "[kernels][cbt]") {
    // a 10 x 10 grid in the plane z = 0: value 1 above the diagonal x + y = 9, 0 below (none on it)
    Cloud c;
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 10; ++x) {
            if (x + y == 9) continue;
            c.pos.push_back({double(x), double(y), 0});
            c.value.push_back(x + y > 9 ? 1 : 0);
        }
    c.finish();
    for (double vs : {1.0, 1.0 / 9}) {  // raw and a value scale comparable to the positions
        const ClusterSplitPlane pl = pca_split_plane(c.pos, c.value, c.idx, c.centre, c.mean, 1.0 / 12.7, vs);
        INFO("value scale " << vs);
        CHECK_FALSE(pl.second);
        CHECK(std::abs(norm(pl.normal) - 1) < 1e-12);
        CHECK(std::abs(std::abs(pl.normal.x) - std::sqrt(0.5)) < 1e-6);
        CHECK(std::abs(std::abs(pl.normal.y) - std::sqrt(0.5)) < 1e-6);
        const auto s = sides(c, pl.normal);
        // each side holds one value only
        CHECK(((s[0][0] == 0 && s[1][1] == 0) || (s[0][1] == 0 && s[1][0] == 0)));
    }
    // an axis-aligned split through the centre mixes both values on both sides
    for (const Vec3 axis : {Vec3{1, 0, 0}, Vec3{0, 1, 0}}) {
        const auto s = sides(c, axis);
        CHECK((s[0][0] > 0 && s[0][1] > 0 && s[1][0] > 0 && s[1][1] > 0));
    }
    // the partition puts exactly the samples behind the plane first
    const ClusterSplitPlane pl = pca_split_plane(c.pos, c.value, c.idx, c.centre, c.mean, 1, 1);
    std::vector<std::uint32_t> idx = c.idx;
    const std::size_t m = partition_by_plane(c.pos, idx, c.centre, pl.normal);
    CHECK(m == 45);
    for (std::size_t i = 0; i < idx.size(); ++i) CHECK((dot(c.pos[idx[i]] - c.centre, pl.normal) < 0) == (i < m));
}

TEST_CASE("PCA split falls back to the second eigenvector when the first is the value axis", "[kernels][cbt]") {
    // values uncorrelated with position and spread far more than the positions: e1 = (0, 0, 0, 1)
    Cloud c;
    c.pos = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0.5}, {1, 1, 0.5}, {1, 0, 0.5}, {0, 1, 0.5}};
    c.value = {10, 10, -10, -10, 10, 10, -10, -10};
    c.finish();
    const ClusterSplitPlane pl = pca_split_plane(c.pos, c.value, c.idx, c.centre, c.mean, 1, 1);
    CHECK(pl.second);
    CHECK(std::abs(norm(pl.normal) - 1) < 1e-12);
    std::vector<std::uint32_t> idx = c.idx;
    const std::size_t m = partition_by_plane(c.pos, idx, c.centre, pl.normal);
    CHECK(m > 0);
    CHECK(m < idx.size());
}

TEST_CASE("PCA split of a cluster without extent has no normal, collinear and coplanar ones split", "[kernels][cbt]") {
    Cloud same;
    same.pos = {{1, 2, 3}, {1, 2, 3}, {1, 2, 3}};
    same.value = {0, 5, 9};
    same.finish();
    const ClusterSplitPlane p0 = pca_split_plane(same.pos, same.value, same.idx, same.centre, same.mean, 1, 1);
    CHECK(norm(p0.normal) == 0);
    Cloud line;
    for (int i = 0; i < 20; ++i) {
        line.pos.push_back({i * 1.0, i * 2.0, i * -0.5});
        line.value.push_back(i < 10 ? 0 : 1);
    }
    line.finish();
    const ClusterSplitPlane p1 = pca_split_plane(line.pos, line.value, line.idx, line.centre, line.mean, 0.1, 1);
    std::vector<std::uint32_t> idx = line.idx;
    CHECK(partition_by_plane(line.pos, idx, line.centre, p1.normal) == 10);
}

TEST_CASE("partition_by_plane: the chunked path of large clusters partitions, the same for any thread count", "[kernels][cbt]") {
    std::vector<Vec3> pos;
    const std::size_t n = 200000;
    for (std::size_t i = 0; i < n; ++i) pos.push_back({std::sin(i * 0.37), std::cos(i * 0.11), double(i % 7)});
    std::vector<std::uint32_t> start(n);
    std::iota(start.begin(), start.end(), 0u);
    std::reverse(start.begin(), start.end());
    const Vec3 c{0.1, 0, 3}, nrm = normalized(Vec3{1, 2, 0.3});
    auto behind = [&](std::uint32_t j) { return dot(pos[j] - c, nrm) < 0; };
    const auto expect = static_cast<std::size_t>(std::count_if(start.begin(), start.end(), behind));
    std::vector<std::uint32_t> ref;
    for (int t : {1, 2, 4}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t);
        std::vector<std::uint32_t> idx = start;
        const std::size_t m = partition_by_plane(pos, idx, c, nrm);
        CHECK(m == expect);
        for (std::size_t i = 0; i < n; ++i) REQUIRE(behind(idx[i]) == (i < m));
        std::vector<std::uint32_t> sorted = idx;
        std::sort(sorted.begin(), sorted.end());
        for (std::size_t i = 0; i < n; ++i) REQUIRE(sorted[i] == i);  // a permutation
        if (ref.empty()) ref = idx;
        else CHECK(idx == ref);
    }
}
