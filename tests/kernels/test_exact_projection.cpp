// Tests for kernels/exact_projection.hpp (section 3.3.1, Eqs. 3.2-3.3): the ray cubic against direct
// evaluation, projections on random active cells (residual, inside the cell, miss rate), linear fields
// against the analytic projection, and a sampled sphere distance field against the sphere.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/cubic_solver.hpp"
#include "kernels/exact_projection.hpp"
#include "kernels/trilinear.hpp"

using namespace meshless;

namespace {

bool is_active(const double c[8], double iso) {
    int above = 0;
    for (int i = 0; i < 8; ++i) above += c[i] >= iso;
    return above > 0 && above < 8;
}

double value_at(const double c[8], const Vec3& x) { return trilinear(c, x.x, x.y, x.z).value; }

bool in_cell(const Vec3& x) {
    return x.x >= 0 && x.x <= 1 && x.y >= 0 && x.y <= 1 && x.z >= 0 && x.z <= 1;
}

}  // namespace

TEST_CASE("exact: ray cubic coefficients reproduce f(p + t dir) - iso", "[exact]") {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> V(0.0, 255.0), P(-0.5, 1.5), D(-2.0, 2.0), T(-3.0, 3.0);
    for (int trial = 0; trial < 20000; ++trial) {
        double c[8];
        for (double& v : c) v = V(rng);
        const Vec3 p{P(rng), P(rng), P(rng)}, d{D(rng), D(rng), D(rng)};
        const double iso = V(rng), t = T(rng);
        const auto k = trilinear_ray_cubic(c, p, d, iso);
        const double want = value_at(c, p + d * t) - iso;
        REQUIRE(cubic_value(k, t) == Approx(want).margin(1e-9 * 255.0 * 64.0));
    }
}

TEST_CASE("exact: random active cells project onto the isosurface inside the cell", "[exact]") {
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> V(0.0, 255.0), P(0.0, 1.0);
    const double iso = 100.5;
    const double tol = 1e-4 * 255.0;
    for (int centred = 1; centred >= 0; --centred) {
        int cells = 0, missed = 0, gradient_hits = 0;
        double worst = 0.0;
        while (cells < 100000) {
            double c[8];
            for (double& v : c) v = V(rng);
            if (!is_active(c, iso)) continue;
            ++cells;
            const Vec3 p = centred ? Vec3{0.5, 0.5, 0.5} : Vec3{P(rng), P(rng), P(rng)};
            const ExactResult r = exact_project_cell(c, p, iso);
            if (r.status == ExactStatus::missed) { ++missed; continue; }
            gradient_hits += r.ray == 0;
            const double res = std::fabs(value_at(c, r.local) - iso);
            worst = std::max(worst, res);
            INFO("residual " << res << " ray " << r.ray);
            REQUIRE(res <= tol);
            REQUIRE(in_cell(r.local));
            if (r.ray == 0) {  // on the gradient line through p
                const Vec3 g = trilinear(c, p.x, p.y, p.z).grad;
                REQUIRE(norm(cross(r.local - p, g)) <= 1e-9 * norm(g) * (1.0 + norm(r.local - p)));
            }
        }
        const double miss_rate = double(missed) / cells;
        WARN((centred ? "cell centre" : "random p") << ": missed " << missed << " of " << cells << " ("
             << 100.0 * miss_rate << " %), gradient-ray hits " << 100.0 * gradient_hits / cells
             << " %, worst |f - iso| " << worst);
        REQUIRE(miss_rate < 0.01);
    }
}

TEST_CASE("exact: gradient ray returns the nearest crossing inside the cell (dense scan oracle)", "[exact]") {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> V(0.0, 255.0);
    const double iso = 100.5;
    const Vec3 p{0.5, 0.5, 0.5};
    int checked = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        double c[8];
        for (double& v : c) v = V(rng);
        if (!is_active(c, iso)) continue;
        const ExactResult r = exact_project_cell(c, p, iso);
        if (r.status != ExactStatus::ok || r.ray != 0) continue;
        const Vec3 g = normalized(trilinear(c, p.x, p.y, p.z).grad);
        const double t_hit = dot(r.local - p, g);
        // scan |t| < |t_hit| - margin on both sides: f - iso keeps the sign of f(p) - iso
        const double s0 = value_at(c, p) - iso;
        const int n = 2000;
        for (int i = 1; i < n; ++i) {
            const double t = (std::fabs(t_hit) - 1e-6) * i / n;
            for (double sgn : {-1.0, 1.0}) {
                const Vec3 x = p + g * (sgn * t);
                if (!in_cell(x)) continue;
                REQUIRE((value_at(c, x) - iso) * s0 > 0.0);
            }
        }
        ++checked;
    }
    REQUIRE(checked > 100);
}

TEST_CASE("exact: linear fields give the analytic projection along the gradient", "[exact]") {
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<double> U(-50.0, 50.0), S(-0.499, 0.499);
    const Vec3 p{0.5, 0.5, 0.5};
    for (int trial = 0; trial < 20000; ++trial) {
        const double f0 = U(rng);
        const Vec3 g{U(rng), U(rng), U(rng)};
        if (norm(g) < 1.0) continue;
        double c[8];
        for (int i = 0; i < 8; ++i) c[i] = f0 + dot(g, Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
        // iso chosen so that the analytic projection lies within 0.5 of the centre, hence in the cell
        const double iso = f0 + dot(g, p + normalized(g) * S(rng));
        const double fp = f0 + dot(g, p);
        const Vec3 want = p + g * ((iso - fp) / dot(g, g));
        const ExactResult r = exact_project_cell(c, p, iso);
        REQUIRE(r.status == ExactStatus::ok);
        REQUIRE(r.ray == 0);
        REQUIRE(norm(r.local - want) <= 1e-9);
    }
}

TEST_CASE("exact: sampled sphere distance field projects within 0.01 voxel of the sphere", "[exact]") {
    const int n = 72;
    const Vec3 centre{35.3, 36.1, 34.7};
    const double radius = 30.3;  // trilinear error of |x| is <= h^2/(4R) ~ 0.008 voxel here
    std::vector<double> f(std::size_t(n) * n * n);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) f[i + n * (j + std::size_t(n) * k)] = norm(Vec3(i, j, k) - centre);
    int cells = 0, missed = 0;
    double worst = 0.0;
    for (int k = 0; k + 1 < n; ++k)
        for (int j = 0; j + 1 < n; ++j)
            for (int i = 0; i + 1 < n; ++i) {
                double c[8];
                for (int q = 0; q < 8; ++q)
                    c[q] = f[(i + (q & 1)) + n * ((j + ((q >> 1) & 1)) + std::size_t(n) * (k + ((q >> 2) & 1)))];
                if (!is_active(c, radius)) continue;
                ++cells;
                const ExactResult r = exact_project_cell(c, {0.5, 0.5, 0.5}, radius);
                if (r.status != ExactStatus::ok) { ++missed; continue; }
                const Vec3 w = Vec3(i, j, k) + r.local;
                worst = std::max(worst, std::fabs(norm(w - centre) - radius));
            }
    WARN("sphere R=" << radius << ": " << cells << " active cells, missed " << missed
         << ", worst distance to sphere " << worst << " voxel");
    REQUIRE(cells > 10000);
    REQUIRE(missed == 0);
    REQUIRE(worst <= 0.01);
}
