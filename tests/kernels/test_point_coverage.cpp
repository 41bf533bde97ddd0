// PointCoverage against brute force on a regular grid with a hole.
#include <catch2/catch.hpp>

#include <cmath>

#include "kernels/errors.hpp"
#include "kernels/point_coverage.hpp"

using namespace meshless;

TEST_CASE("coverage: inside a grid yes, in a hole and far outside no", "[coverage]") {
    std::vector<Vec3> pts;
    for (int k = 0; k < 10; ++k)
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 10; ++i)
                if (!(i >= 3 && i <= 6 && j >= 3 && j <= 6 && k >= 3 && k <= 6)) pts.push_back({double(i), double(j), double(k)});
    const PointCoverage c(pts, 1.0);  // reach = 8th-neighbour distance = sqrt(2) on a unit grid
    CHECK(c.covered({0.5, 0.5, 0.5}));
    CHECK(c.covered({8.2, 1.1, 4.9}));
    CHECK(!c.covered({4.5, 4.5, 4.5}));  // the hole's centre is 2 units from any point
    CHECK(!c.covered({20, 20, 20}));
    std::vector<Vec3> q{{1, 1, 1}, {4.5, 4.5, 4.5}};
    std::vector<double> v{1, 2};
    std::vector<Vec3> g(2);
    CHECK(c.mask(q, v, g) == 1);
    CHECK(v[0] == 1);
    CHECK(std::isnan(v[1]));
    CHECK(std::isnan(g[1].x));
}

namespace {
double smooth(const Vec3& p) { return std::sin(3 * p.x) + std::cos(2 * p.y) * p.z; }
}  // namespace

TEST_CASE("coverage does not cut holes inside random data, and stops at its edge", "[coverage]") {
    // 3000 uniform points in the unit cube: before the surround test, 4 of 6000 interior positions
    // fell in gaps a little wider than the local spacing and came out NaN
    std::vector<Vec3> pts;
    std::vector<double> val;
    unsigned r = 3;
    auto u = [&] { r = r * 1103515245u + 12345u; return (r >> 8) / double(1 << 24); };
    for (int i = 0; i < 3000; ++i) {
        pts.push_back({u(), u(), u()});
        val.push_back(smooth(pts.back()));
    }
    const PointCoverage c(pts, val, 1.0);
    int uncovered = 0;
    for (int i = 0; i < 6000; ++i) uncovered += !c.covered({0.1 + 0.8 * u(), 0.1 + 0.8 * u(), 0.1 + 0.8 * u()});
    CHECK(uncovered == 0);
    // beyond a face by several spacings (mean spacing ~0.07): outside
    for (double y : {0.2, 0.5, 0.8}) {
        CHECK(!c.covered({1.35, y, 0.5}));
        CHECK(!c.covered({0.5, -0.35, y}));
    }
}

TEST_CASE("apply: values kept within the data range, outside handled per --extrapolate", "[coverage]") {
    std::vector<Vec3> pts;
    std::vector<double> val;
    for (int k = 0; k < 6; ++k)
        for (int j = 0; j < 6; ++j)
            for (int i = 0; i < 6; ++i) {
                pts.push_back({double(i), double(j), double(k)});
                val.push_back(i);  // 0..5
            }
    const PointCoverage c(pts, val, 1.0);
    const std::vector<Vec3> at{{2.5, 2.5, 2.5}, {4.9, 1, 1}, {30, 2, 2}};
    for (Extrapolate mode : {Extrapolate::nan, Extrapolate::clamp, Extrapolate::nearest}) {
        std::vector<double> v{2.5, 7.0, 99.0};  // the third position lies far outside the data
        std::vector<Vec3> g(3, Vec3{1, 0, 0});
        const SupportCounts n = c.apply(at, v, g, mode);
        CHECK(n.uncovered == 1);
        CHECK(v[0] == 2.5);
        CHECK(g[0].x == 1);
        CHECK(v[1] == 5.0);  // an overshoot inside the data is kept within its range, gradient 0
        CHECK(g[1].x == 0);
        if (mode == Extrapolate::nan) {
            CHECK(std::isnan(v[2]));
            CHECK(n.clamped == 1);
        } else if (mode == Extrapolate::clamp) {
            CHECK(v[2] == 5.0);
            CHECK(n.clamped == 2);
        } else {
            CHECK(v[2] == 5.0);  // the nearest data point is (5, 2, 2)
            CHECK(g[2].x == 0);
        }
    }
    // without values: only the mask
    const PointCoverage m(pts, 1.0);
    std::vector<double> v{2.5, 7.0, 99.0};
    std::vector<Vec3> g;
    const SupportCounts n = m.apply(at, v, g, Extrapolate::clamp);
    CHECK(n.clamped == 0);
    CHECK(v[1] == 7.0);
    CHECK(std::isnan(v[2]));
    CHECK_THROWS_AS(PointCoverage(pts, std::vector<double>(3), 1.0), InvalidArgument);
}
