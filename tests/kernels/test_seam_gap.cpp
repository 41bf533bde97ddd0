// Tests for kernels/seam_gap.hpp: points of two blocks on one plane have no gap; the same blocks
// offset by a known distance along the normal report that distance; same-block neighbours and
// non-overlapping splats are not pairs; the curvature term of points on a sphere.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "kernels/errors.hpp"
#include "kernels/seam_gap.hpp"

using namespace meshless;

namespace {

struct Cloud {
    std::vector<Vec3> pos, normal;
    std::vector<float> radius;
    std::vector<std::uint32_t> block;
};

/// Two interleaved blocks of points on the plane z = 0 (block 1 lifted by `lift`).
Cloud plane(double lift) {
    Cloud c;
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i) {
            const std::uint32_t b = (i + j) % 2;
            c.pos.push_back({i * 0.1, j * 0.1, b ? lift : 0.0});
            c.normal.push_back({0, 0, 1});
            c.radius.push_back(0.15f);
            c.block.push_back(b);
        }
    return c;
}

}  // namespace

TEST_CASE("seam gaps: one plane has none, a lifted block shows its offset", "[seam_gap]") {
    Cloud c = plane(0.0);
    SeamGaps g = seam_gaps(c.pos, c.normal, c.radius, c.block, INFINITY);
    CHECK(g.pairs > 0);
    CHECK(g.max_gap == 0.0);
    c = plane(0.01);
    g = seam_gaps(c.pos, c.normal, c.radius, c.block, INFINITY);
    CHECK(g.max_gap == Approx(0.01));
    CHECK(g.p99_gap == Approx(0.01));
    // within blocks: the plane's own points, no gap
    const SeamGaps w = seam_gaps(c.pos, c.normal, c.radius, c.block, INFINITY, /*across=*/false);
    CHECK(w.pairs > 0);
    CHECK(w.max_gap == Approx(0.0).margin(1e-12));
    // one block only: no pairs
    std::fill(c.block.begin(), c.block.end(), 3u);
    CHECK(seam_gaps(c.pos, c.normal, c.radius, c.block, INFINITY).pairs == 0);
    // splats too small to overlap: no pairs
    Cloud far = plane(0.01);
    std::fill(far.radius.begin(), far.radius.end(), 0.05f);
    CHECK(seam_gaps(far.pos, far.normal, far.radius, far.block, INFINITY).pairs == 0);
    CHECK_THROWS_AS(seam_gaps(c.pos, c.normal, std::span<const float>(c.radius).first(3), c.block, 1.0), InvalidArgument);
}

TEST_CASE("seam gaps: points of two blocks on a sphere stay within the curvature term", "[seam_gap]") {
    Cloud c;
    const double R = 1.0;
    for (int t = 1; t < 40; ++t)
        for (int p = 0; p < 80; ++p) {
            const double th = M_PI * t / 40, ph = 2 * M_PI * p / 80;
            const Vec3 n{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)};
            c.pos.push_back(n * R);
            c.normal.push_back(n);
            c.radius.push_back(0.1f);
            c.block.push_back(static_cast<std::uint32_t>(p % 2));
        }
    const SeamGaps g = seam_gaps(c.pos, c.normal, c.radius, c.block, R);
    CHECK(g.pairs > 0);
    CHECK(g.max_gap > 0);
    CHECK(g.max_gap <= g.max_curvature_term * 1.0001);
}
