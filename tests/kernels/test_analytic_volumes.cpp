// Tests for kernels/analytic_volumes.hpp. Oracles: central differences of the continuous function,
// parametric points on the sphere and torus surfaces (exact distances), Newton projection for the
// gyroid and Marschner-Lobb, name round trips, the grid mapping.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "kernels/analytic_volumes.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

namespace {
const AnalyticField kAll[] = {AnalyticField::sphere, AnalyticField::torus, AnalyticField::gyroid,
                              AnalyticField::marschner_lobb};
}

TEST_CASE("analytic: gradients match central differences", "[mc]") {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(-0.95, 0.95);
    for (AnalyticField f : kAll) {
        INFO(to_string(f));
        for (int t = 0; t < 200; ++t) {
            const Vec3 p{U(rng), U(rng), U(rng)};
            if (norm(p) < 0.05 || std::hypot(p.x, p.y) < 0.05) continue;  // singular points
            const double h = 1e-6;
            const Vec3 g = analytic_gradient(f, p);
            const Vec3 fd{(analytic_value(f, p + Vec3{h, 0, 0}) - analytic_value(f, p - Vec3{h, 0, 0})) / (2 * h),
                          (analytic_value(f, p + Vec3{0, h, 0}) - analytic_value(f, p - Vec3{0, h, 0})) / (2 * h),
                          (analytic_value(f, p + Vec3{0, 0, h}) - analytic_value(f, p - Vec3{0, 0, h})) / (2 * h)};
            CHECK(norm(g - fd) < 1e-5 * (1.0 + norm(g)));
        }
    }
}

TEST_CASE("analytic: sphere and torus distances are exact", "[mc]") {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> A(0, 2 * M_PI), D(-0.15, 0.15);
    const double rs = default_iso(AnalyticField::sphere), rt = default_iso(AnalyticField::torus);
    for (int t = 0; t < 200; ++t) {
        const double th = A(rng), ph = A(rng), d = D(rng);
        // sphere: point on the surface, then moved d along the normal
        const Vec3 n{std::cos(th) * std::sin(ph), std::sin(th) * std::sin(ph), std::cos(ph)};
        const Vec3 ps = n * rs;
        CHECK(analytic_value(AnalyticField::sphere, ps) == Approx(rs).margin(1e-12));
        CHECK(analytic_distance(AnalyticField::sphere, rs, ps + n * d) == Approx(std::abs(d)).margin(1e-12));
        // torus: core circle radius 0.5 in z=0, tube angle ph
        const Vec3 core{0.5 * std::cos(th), 0.5 * std::sin(th), 0};
        const Vec3 tn{std::cos(ph) * std::cos(th), std::cos(ph) * std::sin(th), std::sin(ph)};
        const Vec3 pt = core + tn * rt;
        CHECK(analytic_value(AnalyticField::torus, pt) == Approx(rt).margin(1e-12));
        CHECK(dot(normalized(analytic_gradient(AnalyticField::torus, pt)), tn) == Approx(1.0).margin(1e-9));
        CHECK(analytic_distance(AnalyticField::torus, rt, pt + tn * d) == Approx(std::abs(d)).margin(1e-12));
    }
}

TEST_CASE("analytic: gyroid and Marschner-Lobb distance estimates", "[mc]") {
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> U(-0.9, 0.9);
    for (AnalyticField f : {AnalyticField::gyroid, AnalyticField::marschner_lobb}) {
        INFO(to_string(f));
        const double iso = default_iso(f);
        int tested = 0;
        for (int t = 0; t < 400 && tested < 100; ++t) {
            // a surface point by Newton from a random start
            Vec3 q{U(rng), U(rng), U(rng)};
            bool ok = false;
            for (int it = 0; it < 50; ++it) {
                const double fq = analytic_value(f, q) - iso;
                if (std::abs(fq) < 1e-13) { ok = true; break; }
                const Vec3 g = analytic_gradient(f, q);
                if (dot(g, g) < 1e-6) break;
                q = q - g * (fq / dot(g, g));
            }
            if (!ok) continue;
            const Vec3 g = analytic_gradient(f, q);
            if (norm(g) < 0.5) continue;  // keep away from near-critical points
            ++tested;
            CHECK(analytic_distance(f, iso, q) < 1e-9);
            const double d = 2e-4;  // small against the curvature radius (ML features are ~0.01)
            const double est = analytic_distance(f, iso, q + normalized(g) * d);
            CHECK(est <= d * 1.05);  // the distance to q is d; the estimate is near the true one
            CHECK(est >= d * 0.95);
        }
        CHECK(tested > 20);
    }
}

TEST_CASE("analytic: volumes sample the functions on [-1,1]^3", "[mc]") {
    for (AnalyticField f : kAll) {
        INFO(to_string(f));
        const std::int64_t n = 17;
        const Volume v = make_analytic_volume(f, n);
        CHECK(v.type == SampleType::f32);
        CHECK(v.grid.dims == std::array<std::int64_t, 3>{n, n, n});
        CHECK(v.grid.origin[0] == -1.0);
        CHECK(v.grid.spacing[2] == Approx(2.0 / (n - 1)));
        const VolumeView vw = v.view();
        for (std::int64_t t = 0; t < n; t += 3) {
            const std::int64_t i = t, j = (t * 7) % n, k = (t * 5 + 3) % n;
            const Vec3 p{-1 + v.grid.spacing[0] * i, -1 + v.grid.spacing[1] * j, -1 + v.grid.spacing[2] * k};
            CHECK(vw.at(i, j, k) == static_cast<float>(analytic_value(f, p)));
        }
        // the default isosurface exists inside the grid
        const auto range = v.value_range();
        CHECK(range[0] < default_iso(f));
        CHECK(range[1] > default_iso(f));
    }
    CHECK_THROWS_AS(make_analytic_volume(AnalyticField::sphere, 1), InvalidArgument);
    const auto ml = make_analytic_volume(AnalyticSpec{AnalyticField::marschner_lobb, 20}).value_range();
    CHECK(ml[0] >= 0.0);
    CHECK(ml[1] <= 1.0);
    // Marschner-Lobb on the axis: rho = cos(2 pi 6) = 1, value = (1 - sin(pi z/2) + 2 alpha) / (2 (1+alpha))
    CHECK(analytic_value(AnalyticField::marschner_lobb, {0, 0, 0.3}) ==
          Approx((1 - std::sin(M_PI * 0.15) + 0.5) / 2.5));
}

TEST_CASE("analytic: names round trip", "[mc]") {
    for (AnalyticField f : kAll) CHECK(parse_analytic_field(to_string(f)) == f);
    CHECK(parse_analytic_field("marschner_lobb") == AnalyticField::marschner_lobb);
    CHECK(parse_analytic_field("marschner-lobb") == AnalyticField::marschner_lobb);
    CHECK(std::string(to_string(AnalyticField::marschner_lobb)) == "ml");
    CHECK_FALSE(parse_analytic_field("cube").has_value());
    CHECK_FALSE(parse_analytic_field("").has_value());
}
