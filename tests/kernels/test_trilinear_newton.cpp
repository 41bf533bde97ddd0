// Tests for kernels/trilinear.hpp (Eq. 3.1) and kernels/newton_projection.hpp (section 3.3.2, Eq. 3.5,
// displacement criterion of Fig. 3.3). Oracles: linear fields (reproduced exactly by trilinear
// interpolation, projected exactly by one Newton step), central differences, corner values.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "kernels/newton_projection.hpp"
#include "kernels/trilinear.hpp"

using namespace meshless;

namespace {

struct Linear {
    double f0;
    Vec3 g;
    double operator()(const Vec3& x) const { return f0 + dot(g, x); }
};

void corners_of(const Linear& f, double c[8]) {
    for (int i = 0; i < 8; ++i) c[i] = f(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
}

}  // namespace

TEST_CASE("trilinear: linear fields are reproduced exactly, gradient is constant", "[exact]") {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> U(-100.0, 100.0), P(-0.5, 1.5);
    for (int trial = 0; trial < 10000; ++trial) {
        const Linear f{U(rng), {U(rng), U(rng), U(rng)}};
        double c[8];
        corners_of(f, c);
        const Vec3 x{P(rng), P(rng), P(rng)};  // inside and (extrapolated) outside the cell
        const ValueGrad vg = trilinear(c, x.x, x.y, x.z);
        REQUIRE(vg.value == Approx(f(x)).margin(1e-11));
        REQUIRE(vg.grad.x == Approx(f.g.x).margin(1e-11));
        REQUIRE(vg.grad.y == Approx(f.g.y).margin(1e-11));
        REQUIRE(vg.grad.z == Approx(f.g.z).margin(1e-11));
    }
}

TEST_CASE("trilinear: corners reproduced, gradient matches central differences", "[exact]") {
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> V(0.0, 255.0), P(0.0, 1.0);
    for (int trial = 0; trial < 10000; ++trial) {
        double c[8];
        for (double& v : c) v = V(rng);
        for (int i = 0; i < 8; ++i) {
            const ValueGrad vg = trilinear(c, i & 1, (i >> 1) & 1, (i >> 2) & 1);
            // c0 + 1*(c1 - c0) form: reproduced to a few ulps of the largest corner, not bit-exactly
            REQUIRE(vg.value == Approx(c[i]).margin(1e-12));
        }
        const Vec3 x{P(rng), P(rng), P(rng)};
        const ValueGrad vg = trilinear(c, x.x, x.y, x.z);
        const double h = 1e-4;
        const double dx = (trilinear(c, x.x + h, x.y, x.z).value - trilinear(c, x.x - h, x.y, x.z).value) / (2 * h);
        const double dy = (trilinear(c, x.x, x.y + h, x.z).value - trilinear(c, x.x, x.y - h, x.z).value) / (2 * h);
        const double dz = (trilinear(c, x.x, x.y, x.z + h).value - trilinear(c, x.x, x.y, x.z - h).value) / (2 * h);
        // f is linear in each variable, so central differences are exact up to rounding
        REQUIRE(vg.grad.x == Approx(dx).margin(1e-6));
        REQUIRE(vg.grad.y == Approx(dy).margin(1e-6));
        REQUIRE(vg.grad.z == Approx(dz).margin(1e-6));
    }
}

TEST_CASE("trilinear: world gradient divides by the cell size", "[exact]") {
    // f(X) = 3 X + 5 Y - 2 Z in world units on a cell of size (2, 0.5, 4): local gradient = g * s
    const Vec3 s{2.0, 0.5, 4.0};
    const Linear f{0.0, {3.0 * s.x, 5.0 * s.y, -2.0 * s.z}};
    double c[8];
    corners_of(f, c);
    const Vec3 gw = to_world_gradient(trilinear(c, 0.3, 0.6, 0.9).grad, s);
    REQUIRE(gw.x == Approx(3.0));
    REQUIRE(gw.y == Approx(5.0));
    REQUIRE(gw.z == Approx(-2.0));
}

TEST_CASE("newton: one step lands exactly on the isosurface of a linear field", "[exact]") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> U(-10.0, 10.0);
    for (int trial = 0; trial < 10000; ++trial) {
        const Linear f{U(rng), {U(rng), U(rng), U(rng)}};
        if (dot(f.g, f.g) < 1e-3) continue;
        const Vec3 p{U(rng), U(rng), U(rng)};
        const double iso = U(rng);
        const NewtonResult r = newton_step(p, f(p), f.g, iso, 1e300);
        REQUIRE(r.status == NewtonStatus::ok);
        REQUIRE(f(r.pos) == Approx(iso).margin(1e-9 * (1.0 + std::fabs(f(p)))));
        // the step is along the gradient: it is the orthogonal (closest-point) projection
        const Vec3 step = r.pos - p;
        REQUIRE(norm(cross(step, f.g)) <= 1e-9 * (1.0 + norm(step) * norm(f.g)));
        REQUIRE(norm(step) == Approx(std::fabs(iso - f(p)) / norm(f.g)).epsilon(1e-10));
    }
}

TEST_CASE("newton: displacement criterion rejects steps longer than half the cell diagonal", "[exact]") {
    const Vec3 cell{1.0, 2.0, 2.0};  // diagonal 3
    const double dd = displacement_threshold(cell);
    REQUIRE(dd == Approx(1.5));
    const Vec3 g = normalized(Vec3{1.0, 1.0, 0.0}) * 10.0;  // |grad| = 10: displacement = |iso - f| / 10
    const Vec3 p{0.5, 1.0, 1.0};
    const double f = 40.0;
    // displacement 1.4 < 1.5: accepted; 1.6 > 1.5: rejected but the tentative position is reported
    NewtonResult r = newton_step(p, f, g, f + 14.0, dd);
    REQUIRE(r.status == NewtonStatus::ok);
    REQUIRE(norm(r.pos - p) == Approx(1.4));
    r = newton_step(p, f, g, f - 16.0, dd);
    REQUIRE(r.status == NewtonStatus::too_far);
    REQUIRE(norm(r.pos - p) == Approx(1.6));
    // flat gradient
    r = newton_step(p, f, Vec3{0, 0, 0}, f + 1.0, dd);
    REQUIRE(r.status == NewtonStatus::flat);
    REQUIRE((r.pos.x == p.x && r.pos.y == p.y && r.pos.z == p.z));
}
