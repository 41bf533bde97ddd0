// PointCoverage against brute force on a regular grid with a hole.
#include <catch2/catch.hpp>

#include <cmath>

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
