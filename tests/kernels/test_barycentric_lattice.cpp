// kernels/barycentric_lattice.hpp and kernels/multiblock_splat_radius.hpp (dissertation section 4.4):
// the lattice has n(n+1)/2 samples, all strictly inside the triangle, distinct, weights summing to 1,
// spaced 1/n apart, no sample shared by two triangles sharing an edge; the radius formula against a
// direct evaluation and its geometric meaning (the discs' total area is the triangle's).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <set>

#include "kernels/barycentric_lattice.hpp"
#include "kernels/errors.hpp"
#include "kernels/multiblock_splat_radius.hpp"

using namespace meshless;

TEST_CASE("barycentric lattice: n(n+1)/2 distinct interior samples whose weights sum to 1", "[lattice]") {
    for (int n = 1; n <= 12; ++n) {
        const auto w = barycentric_lattice(n);
        REQUIRE(w.size() == static_cast<std::size_t>(n * (n + 1) / 2));
        REQUIRE(w.size() == lattice_size(n));
        std::set<std::array<long, 3>> seen;
        for (const auto& s : w) {
            CHECK_THAT(s[0] + s[1] + s[2], Catch::WithinAbs(1.0, 1e-15));
            for (double x : s) {
                CHECK(x >= 1.0 / (3.0 * n) - 1e-15);  // interior: never on an edge or a corner
                CHECK(x < 1.0);
                // on the lattice: (integer + 1/3) / n
                const double k = x * n - 1.0 / 3.0;
                CHECK_THAT(k, Catch::WithinAbs(std::round(k), 1e-12));
            }
            seen.insert({std::lround(s[0] * 3 * n), std::lround(s[1] * 3 * n), std::lround(s[2] * 3 * n)});
        }
        CHECK(seen.size() == w.size());
    }
    const auto c = barycentric_lattice(1);
    CHECK_THAT(c[0][0], Catch::WithinAbs(1.0 / 3.0, 1e-15));
    CHECK_THAT(c[0][1], Catch::WithinAbs(1.0 / 3.0, 1e-15));
}

TEST_CASE("barycentric lattice: the mean of the samples is the centroid, neighbours across an edge share no point", "[lattice]") {
    const int n = 4;
    const auto w = barycentric_lattice(n);
    double m[3] = {0, 0, 0};
    for (const auto& s : w)
        for (int a = 0; a < 3; ++a) m[a] += s[a] / static_cast<double>(w.size());
    for (double x : m) CHECK_THAT(x, Catch::WithinAbs(1.0 / 3.0, 1e-14));
    // two triangles sharing the edge (a, b): their samples lie strictly on either side of it
    const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0.3, 1, 0}, d{0.6, -1, 0};
    for (const auto& s : w) {
        CHECK(barycentric_point(s, a, b, c).y > 0);
        CHECK(barycentric_point(s, a, b, d).y < 0);
    }
}

TEST_CASE("barycentric lattice: n outside 1..kMaxLatticeN is refused", "[lattice]") {
    CHECK_THROWS_AS(barycentric_lattice(0), InvalidArgument);
    CHECK_THROWS_AS(barycentric_lattice(kMaxLatticeN + 1), InvalidArgument);
    CHECK(barycentric_lattice(kMaxLatticeN).size() == lattice_size(kMaxLatticeN));
}

TEST_CASE("multiblock splat radius: r = 2 (1 + d/l) sqrt(2A / (pi n (n+1)))", "[lattice]") {
    const double A = 0.37, l = 1.9;
    for (int n : {1, 2, 3, 7}) {
        const double base = lattice_base_radius(A, n);
        CHECK_THAT(base, Catch::WithinRel(std::sqrt(2 * A / (std::numbers::pi * n * (n + 1))), 1e-15));
        // the n(n+1)/2 discs of radius base cover the triangle's area exactly once
        CHECK_THAT(std::numbers::pi * base * base * static_cast<double>(lattice_size(n)), Catch::WithinRel(A, 1e-14));
        for (double d : {0.0, 0.2, 1.9, 5.0}) {
            const double r = multiblock_splat_radius(A, n, d, l);
            CHECK_THAT(r, Catch::WithinRel(2 * (1 + d / l) * std::sqrt(2 * A / (std::numbers::pi * n * (n + 1))), 1e-15));
            CHECK_THAT(multiblock_splat_radius(base, d, l), Catch::WithinRel(r, 1e-15));
        }
    }
    CHECK(multiblock_splat_radius(1.0, 2, 0.0, 1.0) == 2 * lattice_base_radius(1.0, 2));  // no travel: 2 x base
    CHECK(multiblock_splat_radius(1.0, 2, 1.0, 1.0) == 4 * lattice_base_radius(1.0, 2));  // one diagonal: doubled
    CHECK(lattice_base_radius(0.0, 3) == 0.0);
    CHECK(multiblock_splat_radius(0.5, 0.3, 0.0) == 1.0);  // a zero diagonal does not divide by zero
}
