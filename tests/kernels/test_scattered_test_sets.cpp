// The scattered test sets of the scattered benchmark (kernels/scattered_test_sets.hpp): reproducible
// bytes, counts and the cube, values equal to the analytic field, the clustered distribution's
// 100:1 density contrast measured from the points (a ball at a blob centre against the background
// far from every blob), and the layered distribution's layers (z within the jitter of L levels,
// x, y spread over the whole square).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "kernels/errors.hpp"
#include "kernels/scattered_test_sets.hpp"

using namespace meshless;

namespace {

bool in_cube(const Vec3& p) {
    return p.x >= -1 && p.x <= 1 && p.y >= -1 && p.y <= 1 && p.z >= -1 && p.z <= 1;
}

}  // namespace

TEST_CASE("scattered test sets: same spec same points, counts, cube, analytic values", "[scattered_test_sets]") {
    for (auto d : {ScatterDistribution::uniform, ScatterDistribution::clustered, ScatterDistribution::layered}) {
        const ScatteredSetSpec spec{AnalyticField::gyroid, d, 5000, 7};
        const PointSet a = make_scattered_set(spec), b = make_scattered_set(spec);
        REQUIRE(a.size() == 5000);
        REQUIRE(a.value.size() == 5000);
        REQUIRE(a.blocks.size() == 1);
        CHECK(a.blocks[0].name == "gyroid-" + std::string(to_string(d)) + "-5000");
        bool same = true;
        for (std::size_t i = 0; i < a.size(); ++i) {
            same = same && a.pos[i].x == b.pos[i].x && a.pos[i].y == b.pos[i].y && a.pos[i].z == b.pos[i].z && a.value[i] == b.value[i];
            REQUIRE(in_cube(a.pos[i]));
            REQUIRE(a.value[i] == analytic_value(AnalyticField::gyroid, a.pos[i]));
        }
        CHECK(same);
        const PointSet c = make_scattered_set({AnalyticField::gyroid, d, 5000, 8});
        CHECK(c.pos[0].x != a.pos[0].x);
        CHECK(parse_scatter_distribution(to_string(d)) == d);
    }
    CHECK_FALSE(parse_scatter_distribution("gaussian"));
    CHECK_THROWS_AS(make_scattered_set({AnalyticField::sphere, ScatterDistribution::uniform, 0, 1}), InvalidArgument);
}

TEST_CASE("scattered test sets: clustered density contrast is 100 to 1", "[scattered_test_sets]") {
    const std::size_t n = 400000;
    const PointSet ps = make_scattered_set({AnalyticField::sphere, ScatterDistribution::clustered, n, 3});
    const auto centres = cluster_centres(3);
    // a small ball (radius sigma/3: density >= 95% of the peak, 97% on average) at the first centre, against the
    // background: points whose density is 1 to 1e-6 (farther than ~5.3 sigma from every centre)
    const double r = kClusterSigma / 3;
    std::size_t in_ball = 0, background = 0;
    for (const Vec3& p : ps.pos) {
        if (norm(p - centres[0]) <= r) ++in_ball;
        if (clustered_density(centres, p) < 1 + 99e-6) ++background;
    }
    // the background's volume, by a Monte Carlo estimate on the same rule
    std::size_t bg_hits = 0;
    const int m = 200000;
    for (int i = 0; i < m; ++i) {
        const double t = (i + 0.5) / m;
        const Vec3 x{-1 + 2 * std::fmod(t * 7919.0, 1.0), -1 + 2 * std::fmod(t * 104729.0, 1.0), -1 + 2 * t};
        if (clustered_density(centres, x) < 1 + 99e-6) ++bg_hits;
    }
    const double bg_volume = 8.0 * bg_hits / m;
    const double ball_volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    REQUIRE(bg_volume > 0.5);
    REQUIRE(in_ball > 200);
    const double contrast = (in_ball / ball_volume) / (background / bg_volume);
    INFO("contrast " << contrast << ", ball " << in_ball << ", background " << background << " in " << bg_volume);
    CHECK(contrast > 80);
    CHECK(contrast < 115);
    // the blobs hold most of the points
    CHECK(background < n / 2);
}

TEST_CASE("scattered test sets: layered points lie on L layers spread in x and y", "[scattered_test_sets]") {
    CHECK(layered_layer_count(10) == 4);
    CHECK(layered_layer_count(10000) == 5);
    CHECK(layered_layer_count(1000000) == 25);
    const std::size_t n = 100000;
    const int layers = layered_layer_count(n);
    REQUIRE(layers == 12);
    const double dz = 2.0 / (layers - 1);
    const PointSet ps = make_scattered_set({AnalyticField::marschner_lobb, ScatterDistribution::layered, n, 1});
    std::vector<std::size_t> per_layer(static_cast<std::size_t>(layers), 0);
    double xlo = 1, xhi = -1, ylo = 1, yhi = -1;
    for (const Vec3& p : ps.pos) {
        const double l = (p.z + 1) / dz;
        const long li = std::lround(l);
        REQUIRE(std::abs(l - static_cast<double>(li)) <= kLayerJitter + 1e-12);
        ++per_layer[static_cast<std::size_t>(li)];
        xlo = std::min(xlo, p.x), xhi = std::max(xhi, p.x), ylo = std::min(ylo, p.y), yhi = std::max(yhi, p.y);
    }
    for (std::size_t c : per_layer) CHECK(std::abs(static_cast<double>(c) - static_cast<double>(n) / layers) < 0.05 * n / layers);
    CHECK(xlo < -0.99);
    CHECK(xhi > 0.99);
    CHECK(ylo < -0.99);
    CHECK(yhi > 0.99);
}
