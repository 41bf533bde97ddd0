// The crack-free oracle (kernels/surface_coverage.hpp) against closed forms: points on the sphere
// with enough radius cover all of it, removing a cap leaves the cap's area uncovered, the sample
// density is the documented 2/spacing^2 per unit area, and displaced / tilted points give the
// distances and angles they were displaced by.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include <array>
#include <span>
#include <string>

#include <tbb/global_control.h>

#include "kernels/errors.hpp"
#include "kernels/field.hpp"
#include "kernels/field_isosurface_samples.hpp"
#include "kernels/splitmix.hpp"
#include "kernels/surface_coverage.hpp"

using namespace meshless;

namespace {

const Box3 kCube{{-1, -1, -1}, {1, 1, 1}};
constexpr double kR = 0.7;  // sphere iso

/// n Fibonacci points on the sphere of radius kR.
std::vector<Vec3> fibonacci(int n) {
    std::vector<Vec3> p;
    const double ga = std::numbers::pi * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double z = 1 - (i + 0.5) * 2.0 / n, r = std::sqrt(1 - z * z);
        p.push_back(Vec3{r * std::cos(ga * i), r * std::sin(ga * i), z} * kR);
    }
    return p;
}

bool same(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z) return false;
    return true;
}

double cap_fraction(double alpha) { return (1 - std::cos(alpha)) / 2; }

}  // namespace

TEST_CASE("surface sampling: on the surface, in the box, 2/spacing^2 per unit area", "[surface_coverage]") {
    SurfaceSampling s;
    s.spacing = 0.02;
    const auto samples = sample_isosurface(AnalyticField::sphere, kR, kCube, s);
    const double area = 4 * std::numbers::pi * kR * kR;
    const double expected = 2 * area / (s.spacing * s.spacing);
    CHECK(std::abs(static_cast<double>(samples.size()) - expected) < 0.03 * expected);
    double worst = 0;
    std::size_t upper = 0;
    for (const Vec3& p : samples) {
        worst = std::max(worst, std::abs(norm(p) - kR));
        upper += p.z > 0;
    }
    CHECK(worst < 1e-9);
    // uniform: half of them on the upper hemisphere, within 4 standard errors
    const double n = static_cast<double>(samples.size());
    CHECK(std::abs(static_cast<double>(upper) / n - 0.5) < 4 * std::sqrt(0.25 / n));
    // same seed, same set; another seed, another set
    CHECK(same(sample_isosurface(AnalyticField::sphere, kR, kCube, s), samples));
    s.seed = 2;
    CHECK(!same(sample_isosurface(AnalyticField::sphere, kR, kCube, s), samples));

    // torus and gyroid: on their surfaces; the margin keeps samples away from the faces
    for (AnalyticField f : {AnalyticField::torus, AnalyticField::gyroid}) {
        SurfaceSampling m;
        m.spacing = 0.04;
        m.margin = 0.1;
        const auto t = sample_isosurface(f, default_iso(f), kCube, m);
        REQUIRE(t.size() > 1000);
        for (const Vec3& p : t) {
            REQUIRE(std::abs(analytic_value(f, p) - default_iso(f)) < 1e-9);
            REQUIRE(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) <= 0.9);
        }
    }
    CHECK_THROWS_AS(sample_isosurface(AnalyticField::sphere, kR, kCube, SurfaceSampling{0, 0, 1}), InvalidArgument);
    CHECK_THROWS_AS(sample_isosurface(AnalyticField::sphere, kR, Box3{{0, 0, 0}, {0, 1, 1}}), InvalidArgument);
}

TEST_CASE("coverage: enough radius covers the sphere, too little does not, a removed cap is uncovered", "[surface_coverage]") {
    SurfaceSampling s;
    s.spacing = 0.015;
    const auto samples = sample_isosurface(AnalyticField::sphere, kR, kCube, s);
    const double n = static_cast<double>(samples.size());
    const auto pts = fibonacci(20000);  // mean spacing sqrt(4 pi R^2 / N) = 0.0175
    SECTION("covered") {
        const std::vector<float> radii(pts.size(), 0.02f);
        const CoverageResult c = surface_coverage(samples, pts, radii);
        CHECK(c.samples == samples.size());
        CHECK(c.covered == c.samples);
        CHECK(c.fraction() == 1.0);
    }
    SECTION("radius far below the spacing leaves most of it uncovered") {
        const std::vector<float> radii(pts.size(), 0.002f);
        CHECK(surface_coverage(samples, pts, radii).fraction() < 0.2);
    }
    SECTION("a cap of half-angle 60 degrees removed") {
        const double alpha = std::numbers::pi / 3, r = 0.02;
        std::vector<Vec3> kept;
        for (const Vec3& p : pts)
            if (p.z <= kR * std::cos(alpha)) kept.push_back(p);
        const std::vector<float> radii(kept.size(), static_cast<float>(r));
        std::vector<std::uint8_t> mask;
        const CoverageResult c = surface_coverage(samples, kept, radii, &mask);
        const double uncovered = 1 - c.fraction();
        // the splats at the cap's rim reach r into it: the hole is a cap of half-angle between
        // alpha - r/R and alpha
        const double se = std::sqrt(0.25 / n);
        CHECK(uncovered > cap_fraction(alpha - r / kR) - 4 * se);
        CHECK(uncovered < cap_fraction(alpha) + 4 * se);
        // uncovered samples lie in the cap; covered samples in the cap lie within r of its rim
        for (std::size_t i = 0; i < samples.size(); ++i) {
            if (!mask[i]) REQUIRE(samples[i].z > kR * std::cos(alpha));
            else REQUIRE(samples[i].z <= kR * std::cos(alpha - 2 * std::asin(r / (2 * kR))) + 1e-9);
        }
    }
    SECTION("non-finite points and radii are skipped and counted") {
        std::vector<Vec3> p = pts;
        std::vector<float> radii(p.size(), 0.02f);
        p[0].x = NAN;
        radii[1] = -1;
        radii[2] = INFINITY;
        const CoverageResult c = surface_coverage(samples, p, radii);
        CHECK(c.nonfinite == 3);
        CHECK(c.fraction() > 0.999);
        CHECK_THROWS_AS(surface_coverage(samples, p, std::vector<float>(3, 1.f)), InvalidArgument);
    }
}

TEST_CASE("point errors: distances and normal angles of displaced points", "[surface_coverage]") {
    SurfaceSampling s;
    s.spacing = 0.05;
    const auto on = sample_isosurface(AnalyticField::sphere, kR, kCube, s);
    REQUIRE(on.size() > 500);
    SplitMix rng{7};
    std::vector<Vec3> p, nrm;
    const double d = 0.01, tilt = 10.0 * std::numbers::pi / 180;
    for (const Vec3& q : on) {
        const Vec3 u = normalized(q);
        p.push_back(q + u * (rng.unit() < 0.5 ? d : -d));
        // a unit normal tilted by exactly `tilt` from VTK's normal -grad f (the sphere field grows
        // outwards, so -grad f points to the centre)
        const Vec3 t = normalized(cross(u, std::abs(u.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0}));
        nrm.push_back(-(u * std::cos(tilt) + t * std::sin(tilt)));
    }
    const PointErrors e = point_errors(AnalyticField::sphere, kR, p, nrm);
    CHECK(e.points == p.size());
    CHECK(e.mean_distance == Approx(d).epsilon(1e-6));
    CHECK(e.max_distance == Approx(d).epsilon(1e-6));
    CHECK(e.normals == p.size());
    CHECK(e.mean_normal_deg == Approx(10.0).epsilon(1e-6));
    CHECK(e.max_normal_deg == Approx(10.0).epsilon(1e-6));
    CHECK(e.reversed == 0);
    // every other normal flipped (pointing towards increasing values): an error of 180 - 10 degrees
    std::vector<Vec3> half = nrm;
    for (std::size_t i = 0; i < half.size(); i += 2) half[i] = -half[i];
    const PointErrors h = point_errors(AnalyticField::sphere, kR, p, half);
    CHECK(h.reversed == (p.size() + 1) / 2);
    CHECK(h.max_normal_deg == Approx(170.0).epsilon(1e-6));
    CHECK(h.mean_normal_deg == Approx(10.0 + 160.0 * static_cast<double>((p.size() + 1) / 2) / static_cast<double>(p.size())).epsilon(1e-6));
    // torus: exact distance too
    const auto ton = sample_isosurface(AnalyticField::torus, 0.25, kCube, s);
    std::vector<Vec3> tp;
    for (const Vec3& q : ton) tp.push_back(q + normalized(analytic_gradient(AnalyticField::torus, q)) * 0.02);
    const PointErrors te = point_errors(AnalyticField::torus, 0.25, tp, {});
    CHECK(te.mean_distance == Approx(0.02).epsilon(1e-6));
    CHECK(te.normals == 0);
    CHECK_THROWS_AS(point_errors(AnalyticField::sphere, kR, p, std::vector<Vec3>(2)), InvalidArgument);
}

namespace {
/// An analytic field as a meshless Field (kernels/field.hpp); NaN where x > cut (outside its support).
class AnalyticAsField final : public Field {
public:
    AnalyticAsField(AnalyticField f, double cut) : f_(f), cut_(cut) {}
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override {
        for (std::size_t i = 0; i < p.size(); ++i) {
            const bool out = p[i].x > cut_;
            value[i] = out ? std::nan("") : analytic_value(f_, p[i]);
            if (!grad.empty()) grad[i] = out ? Vec3{std::nan(""), 0, 0} : analytic_gradient(f_, p[i]);
        }
    }
    std::array<Vec3, 2> bounds() const override { return {kCube.lo, kCube.hi}; }
    std::string name() const override { return "analytic"; }

private:
    AnalyticField f_;
    double cut_;
};
}  // namespace

TEST_CASE("field isosurface sampling: a field's own surface, 2/spacing^2 per unit area, none outside its support", "[surface_coverage]") {
    SurfaceSampling s;
    s.spacing = 0.02;
    const AnalyticAsField sphere(AnalyticField::sphere, 10);
    const auto samples = sample_field_isosurface(sphere, kR, kCube, s);
    const double area = 4 * std::numbers::pi * kR * kR;
    const double expected = 2 * area / (s.spacing * s.spacing);
    CHECK(std::abs(static_cast<double>(samples.size()) - expected) < 0.03 * expected);
    double worst = 0;
    for (const Vec3& p : samples) worst = std::max(worst, std::abs(norm(p) - kR));
    CHECK(worst < 1e-9);
    // the same set for any thread count (seeded per slab), another seed another set
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        CHECK(same(sample_field_isosurface(sphere, kR, kCube, s), samples));
    }
    // where the field is NaN (x > 0.2) nothing is sampled; the rest of the sphere is
    const AnalyticAsField half(AnalyticField::sphere, 0.2);
    const auto part = sample_field_isosurface(half, kR, kCube, s);
    std::size_t beyond = 0;
    for (const Vec3& p : part) beyond += p.x > 0.2;
    CHECK(beyond == 0);
    CHECK(static_cast<double>(part.size()) > 0.5 * static_cast<double>(samples.size()));
    CHECK(part.size() < samples.size());
    CHECK_THROWS_AS(sample_field_isosurface(sphere, kR, kCube, SurfaceSampling{0, 0, 1}), InvalidArgument);
}
