// kernels/field_newton_projection.hpp against oracles: analytic fields whose isosurfaces are known
// spheres (a distance field, a quadratic), the trilinear interpolant of a sampled sphere (points
// must satisfy the trilinear field itself to tolerance and lie within O(h^2) of the true sphere),
// a 1-D arctan whose undamped Newton iteration diverges (step halving must rescue it), and fields
// built to make each kind of drop happen.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "kernels/analytic_volumes.hpp"
#include "kernels/field_newton_projection.hpp"
#include "kernels/trilinear_field.hpp"

using namespace meshless;

namespace {

/// A Field from a value+gradient function (for the analytic oracles).
class LambdaField final : public Field {
public:
    using Fn = std::function<double(const Vec3&, Vec3&)>;
    explicit LambdaField(Fn fn) : fn_(std::move(fn)) {}
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override {
        ++calls;
        for (std::size_t i = 0; i < p.size(); ++i) {
            Vec3 g;
            value[i] = fn_(p[i], g);
            if (!grad.empty()) grad[i] = g;
        }
    }
    std::array<Vec3, 2> bounds() const override { return {Vec3{-1, -1, -1}, Vec3{1, 1, 1}}; }
    std::string name() const override { return "lambda"; }
    mutable int calls = 0;

private:
    Fn fn_;
};

const Vec3 kCentre{0.1, -0.2, 0.05};

/// |p - c|: a distance field whose isosurface r is the sphere of radius r around c.
LambdaField sphere_distance() {
    return LambdaField([](const Vec3& p, Vec3& g) {
        const Vec3 d = p - kCentre;
        const double n = norm(d);
        g = n > 0 ? d * (1.0 / n) : Vec3{};
        return n;
    });
}

/// |p - c|^2: the same spheres, but Newton needs several steps.
LambdaField sphere_quadratic() {
    return LambdaField([](const Vec3& p, Vec3& g) {
        const Vec3 d = p - kCentre;
        g = d * 2.0;
        return dot(d, d);
    });
}

std::vector<Vec3> random_seeds(std::size_t n, double lo, double hi, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1), r(lo, hi);
    std::vector<Vec3> s;
    while (s.size() < n) {
        const Vec3 d{u(rng), u(rng), u(rng)};
        if (norm(d) < 1e-3 || norm(d) > 1) continue;
        s.push_back(kCentre + normalized(d) * r(rng));
    }
    return s;
}

struct Run {
    std::vector<Vec3> pos, grad;
    std::vector<FieldNewtonStatus> status;
    FieldNewtonStats stats;
};

Run project(const Field& f, double iso, const std::vector<Vec3>& seeds, const FieldNewtonParams& p = {},
            const std::vector<double>& limit = {}) {
    Run r;
    r.pos.resize(seeds.size());
    r.grad.resize(seeds.size());
    r.status.resize(seeds.size());
    project_onto_field(f, iso, seeds, p, limit, r.pos, r.grad, r.status, r.stats);
    return r;
}

}  // namespace

TEST_CASE("Newton onto a distance field: one step lands on the sphere", "[field-newton]") {
    const LambdaField f = sphere_distance();
    const auto seeds = random_seeds(1000, 0.2, 0.9, 1);
    FieldNewtonParams p;
    p.tolerance = 1e-9;
    const Run r = project(f, 0.5, seeds, p);
    CHECK(r.stats.input == 1000);
    CHECK(r.stats.converged == 1000);
    CHECK(r.stats.dropped() == 0);
    for (std::size_t i = 0; i < seeds.size(); ++i) {
        REQUIRE(r.status[i] == FieldNewtonStatus::converged);
        REQUIRE(norm(r.pos[i] - kCentre) == Approx(0.5).margin(1e-9));
        // the step is along the gradient: the point stays on the seed's ray from the centre
        REQUIRE(norm(cross(r.pos[i] - kCentre, seeds[i] - kCentre)) < 1e-9);
    }
    // batched: the seeds, one Newton round, and the check of the last (exact) step
    CHECK(f.calls <= 3);
    CHECK(r.stats.evaluations <= 3000);
}

TEST_CASE("Newton onto a quadratic field iterates to the tolerance", "[field-newton]") {
    const LambdaField f = sphere_quadratic();
    const auto seeds = random_seeds(500, 0.05, 0.95, 2);
    for (double tol : {1e-3, 1e-6, 1e-10}) {
        FieldNewtonParams p;
        p.tolerance = tol;
        f.calls = 0;
        const Run r = project(f, 0.25, seeds, p);  // the sphere of radius 0.5
        CHECK(r.stats.converged == 500);
        for (std::size_t i = 0; i < seeds.size(); ++i) {
            REQUIRE(std::abs(norm(r.pos[i] - kCentre) - 0.5) <= 1.01 * tol + 1e-12);
            // normals to increasing values: outward for |p - c|^2
            REQUIRE(dot(r.grad[i], r.pos[i] - kCentre) > 0);
        }
        // quadratic convergence: a handful of rounds, never the cap
        CHECK(f.calls <= 12);
    }
}

TEST_CASE("Newton onto the trilinear interpolant of a sampled sphere", "[field-newton]") {
    const Volume v = make_analytic_volume(AnalyticField::sphere, 48);
    const TrilinearField f(v.view());
    const double h = v.grid.spacing[0];
    std::vector<Vec3> seeds;
    for (const Vec3& s : random_seeds(2000, 0.55, 0.85, 3)) seeds.push_back(s - kCentre);  // centred at 0
    FieldNewtonParams p;
    p.tolerance = 1e-6;
    const Run r = project(f, 0.7, seeds, p);
    CHECK(r.stats.converged == 2000);
    for (std::size_t i = 0; i < seeds.size(); ++i) {
        Vec3 g;
        const double val = f.value(r.pos[i], &g);
        // on the trilinear isosurface to tolerance (first-order distance)
        REQUIRE(std::abs(val - 0.7) <= 1e-6 * norm(g) * 1.01 + 1e-12);
        // and near the true sphere: trilinear interpolation of |p| errs by O(h^2 / r)
        REQUIRE(std::abs(norm(r.pos[i]) - 0.7) < h * h);
        REQUIRE(dot(normalized(r.grad[i]), normalized(r.pos[i])) > 0.99);
    }
}

TEST_CASE("step halving rescues a Newton iteration that diverges undamped", "[field-newton]") {
    // f(x) = atan(x - 0.3): undamped Newton from |x - 0.3| > 1.39 oscillates off to infinity
    const LambdaField f([](const Vec3& p, Vec3& g) {
        const double t = p.x - 0.3;
        g = {1.0 / (1.0 + t * t), 0, 0};
        return std::atan(t);
    });
    const std::vector<Vec3> seeds = {{3.0, 0, 0}, {-4.0, 0.5, 0}, {10.0, 0, -1}};
    FieldNewtonParams p;
    p.tolerance = 1e-10;
    p.max_iterations = 100;
    const Run r = project(f, 0.0, seeds, p);
    CHECK(r.stats.converged == 3);
    for (std::size_t i = 0; i < seeds.size(); ++i) {
        CHECK(r.pos[i].x == Approx(0.3).margin(1e-9));
        CHECK(r.pos[i].y == seeds[i].y);  // moved along the gradient only
    }
    // without halving the same seeds are dropped, not thrown about
    p.max_halvings = 0;
    const Run undamped = project(f, 0.0, seeds, p);
    CHECK(undamped.stats.converged == 0);
    CHECK(undamped.stats.stalled == 3);
}

TEST_CASE("drops are counted by kind, never thrown", "[field-newton]") {
    SECTION("flat: zero gradient at the seed") {
        const LambdaField f = sphere_quadratic();
        const Run r = project(f, 0.25, {kCentre, kCentre + Vec3{0.2, 0, 0}});
        CHECK(r.status[0] == FieldNewtonStatus::flat);
        CHECK(r.status[1] == FieldNewtonStatus::converged);
        CHECK(r.stats.flat == 1);
        CHECK(r.stats.converged == 1);
    }
    SECTION("too far: the surface is beyond the displacement limit") {
        const LambdaField f = sphere_distance();
        const auto seeds = random_seeds(100, 0.1, 0.9, 4);
        FieldNewtonParams p;
        p.max_displacement = 0.2;
        const Run r = project(f, 0.5, seeds, p);
        std::int64_t expect_far = 0;
        for (std::size_t i = 0; i < seeds.size(); ++i) {
            const bool far = std::abs(norm(seeds[i] - kCentre) - 0.5) > 0.2;
            expect_far += far;
            REQUIRE((r.status[i] == FieldNewtonStatus::too_far) == far);
        }
        CHECK(expect_far > 10);
        CHECK(r.stats.too_far == expect_far);
        CHECK(r.stats.converged == 100 - expect_far);
        // a per-seed limit replaces the global one
        const Run r2 = project(f, 0.5, seeds, FieldNewtonParams{}, std::vector<double>(seeds.size(), 0.05));
        std::int64_t far2 = 0;
        for (const Vec3& s : seeds) far2 += std::abs(norm(s - kCentre) - 0.5) > 0.05;
        CHECK(r2.stats.too_far == far2);
    }
    SECTION("no surface: the iteration cannot converge") {
        // |p|^2 + 1 never reaches 0: steps shrink towards the minimum, never converge
        const LambdaField f([](const Vec3& p, Vec3& g) {
            g = p * 2.0;
            return dot(p, p) + 1.0;
        });
        const auto seeds = random_seeds(50, 0.2, 0.9, 5);
        FieldNewtonParams p;
        p.max_iterations = 30;
        const Run r = project(f, 0.0, seeds, p);
        CHECK(r.stats.converged == 0);
        CHECK(r.stats.not_converged + r.stats.stalled + r.stats.flat == 50);
        CHECK(r.stats.dropped() == 50);
        CHECK(r.stats.evaluations <= 50 * 31);
    }
    SECTION("non-finite: NaN outside a half space") {
        const LambdaField f([](const Vec3& p, Vec3& g) {
            g = {1, 0, 0};
            return p.x < 0 ? std::numeric_limits<double>::quiet_NaN() : p.x;
        });
        const Run r = project(f, 0.5, {{-0.5, 0, 0}, {0.9, 0, 0}});
        CHECK(r.status[0] == FieldNewtonStatus::nonfinite);
        CHECK(r.status[1] == FieldNewtonStatus::converged);
        CHECK(r.pos[1].x == Approx(0.5));
        CHECK(r.stats.nonfinite == 1);
    }
    SECTION("max_iterations 0: only seeds already on the surface converge") {
        const LambdaField f = sphere_distance();
        FieldNewtonParams p;
        p.max_iterations = 0;
        const Run r = project(f, 0.5, {kCentre + Vec3{0.5, 0, 0}, kCentre + Vec3{0.7, 0, 0}}, p);
        CHECK(r.status[0] == FieldNewtonStatus::converged);
        CHECK(r.status[1] == FieldNewtonStatus::not_converged);
    }
}

TEST_CASE("final_step: the last within-tolerance step is taken without another evaluation", "[field-newton]") {
    const LambdaField f = sphere_quadratic();
    const auto seeds = random_seeds(300, 0.3, 0.8, 5);
    FieldNewtonParams p;
    p.tolerance = 1e-2;
    f.calls = 0;
    const Run plain = project(f, 0.25, seeds, p);
    const int plain_calls = f.calls;
    p.final_step = true;
    f.calls = 0;
    const Run fin = project(f, 0.25, seeds, p);
    CHECK(f.calls == plain_calls);
    CHECK(fin.stats.converged == 300);
    double worst_plain = 0, worst_final = 0;
    for (std::size_t i = 0; i < seeds.size(); ++i) {
        CHECK(norm(fin.pos[i] - plain.pos[i]) <= 1e-2 * 1.0000001);  // one step of at most the tolerance
        CHECK(fin.grad[i].x == plain.grad[i].x);                      // the gradient where it was evaluated
        worst_plain = std::max(worst_plain, std::abs(norm(plain.pos[i] - kCentre) - 0.5));
        worst_final = std::max(worst_final, std::abs(norm(fin.pos[i] - kCentre) - 0.5));
    }
    CHECK(worst_plain > 1e-3);               // the plain stop is up to the tolerance away
    CHECK(worst_final < 0.1 * worst_plain);  // quadratic convergence: the extra step lands much nearer
}
