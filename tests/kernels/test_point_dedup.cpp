// Near-duplicate removal (kernels/point_dedup.hpp) against brute force: greedy in order, a point is
// dropped exactly when an earlier kept point lies closer than fraction x its radius, for any hash
// cell size (smaller or larger than the search radius); bad parameters are refused.
#include <catch2/catch.hpp>

#include <random>

#include "kernels/errors.hpp"
#include "kernels/point_dedup.hpp"

using namespace meshless;

TEST_CASE("point dedup: greedy in order, equal to brute force for any cell size", "[kernels][scattered]") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1), r(0.01, 0.08);
    std::vector<Vec3> p;
    std::vector<double> rad;
    for (int i = 0; i < 3000; ++i) {
        p.push_back({u(rng), u(rng), 0.1 * u(rng)});
        rad.push_back(r(rng));
        if (i % 7 == 0) {  // an exact and a near duplicate
            p.push_back(p.back());
            rad.push_back(rad.back());
            p.push_back(p.back() + Vec3{1e-4, 0, 0});
            rad.push_back(rad.back());
        }
    }
    const double fraction = 0.5;
    std::vector<bool> expect;
    std::vector<Vec3> kept;
    for (std::size_t i = 0; i < p.size(); ++i) {
        bool close = false;
        for (const Vec3& q : kept) close = close || norm(q - p[i]) < fraction * rad[i];
        expect.push_back(!close);
        if (!close) kept.push_back(p[i]);
    }
    for (double cell : {0.003, 0.02, 0.5}) {
        INFO("cell " << cell);
        PointDedup d(fraction, cell);
        std::size_t mismatches = 0;
        for (std::size_t i = 0; i < p.size(); ++i) mismatches += d.keep(p[i], rad[i]) != expect[i];
        CHECK(mismatches == 0);
        CHECK(d.kept() == static_cast<std::int64_t>(kept.size()));
        CHECK(d.removed() == static_cast<std::int64_t>(p.size() - kept.size()));
    }
    CHECK(kept.size() < p.size() - 800);  // the duplicates went (and more)
    PointDedup none(0, 0.1);
    for (std::size_t i = 0; i < 100; ++i) CHECK(none.keep(p[0], 1.0));
    CHECK_THROWS_AS(PointDedup(-1, 0.1), InvalidArgument);
    CHECK_THROWS_AS(PointDedup(0.5, 0), InvalidArgument);
}
