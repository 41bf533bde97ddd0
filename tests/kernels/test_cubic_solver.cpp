// Tests for kernels/cubic_solver.hpp (section 3.3.1, Eq. 3.3): roots built from known roots, degenerate
// leading coefficients, scaling invariance, and a brute-force bisection oracle.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/cubic_solver.hpp"

using namespace meshless;

namespace {

// (t - r0)(t - r1)(t - r2) * s  ->  {a,b,c,d}
std::array<double, 4> from_roots(double r0, double r1, double r2, double s = 1.0) {
    return {s, -s * (r0 + r1 + r2), s * (r0 * r1 + r0 * r2 + r1 * r2), -s * r0 * r1 * r2};
}

bool close_rel(double x, double y, double rel) {
    return std::fabs(x - y) <= rel * std::max(1.0, std::max(std::fabs(x), std::fabs(y)));
}

// All sign-change roots of the cubic on [-R, R] by grid scan + bisection (brute-force oracle).
std::vector<double> bisection_roots(const std::array<double, 4>& k, double R, int n) {
    std::vector<double> out;
    const double h = 2.0 * R / n;
    double x0 = -R, f0 = cubic_value(k, x0);
    for (int i = 1; i <= n; ++i) {
        const double x1 = -R + i * h, f1 = cubic_value(k, x1);
        if (f0 == 0.0) out.push_back(x0);
        else if (f0 * f1 < 0.0) {
            double lo = x0, hi = x1, flo = f0;
            for (int it = 0; it < 200 && hi - lo > 1e-15 * std::max(1.0, std::fabs(lo)); ++it) {
                const double mid = 0.5 * (lo + hi), fm = cubic_value(k, mid);
                if ((fm < 0) == (flo < 0)) { lo = mid; flo = fm; } else hi = mid;
            }
            out.push_back(0.5 * (lo + hi));
        }
        x0 = x1;
        f0 = f1;
    }
    return out;
}

}  // namespace

TEST_CASE("cubic: random distinct roots are recovered to 1e-9 relative", "[exact]") {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> U(-10.0, 10.0);
    int tested = 0;
    for (int trial = 0; trial < 100000; ++trial) {
        double r[3] = {U(rng), U(rng), U(rng)};
        std::sort(r, r + 3);
        // close roots are ill-conditioned (error ~ eps/gap); keep the gap above 1e-3 for this oracle
        if (r[1] - r[0] < 1e-3 || r[2] - r[1] < 1e-3) continue;
        const auto k = from_roots(r[0], r[1], r[2], trial % 2 ? 1.0 : -2.5);
        double x[3];
        const int n = solve_cubic(k[0], k[1], k[2], k[3], x);
        REQUIRE(n == 3);
        for (int i = 0; i < 3; ++i) {
            INFO("roots " << r[0] << " " << r[1] << " " << r[2] << " got " << x[i]);
            REQUIRE(close_rel(x[i], r[i], 1e-9));
        }
        ++tested;
    }
    REQUIRE(tested > 90000);
}

TEST_CASE("cubic: one real root plus a complex pair", "[exact]") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(-10.0, 10.0);
    for (int trial = 0; trial < 20000; ++trial) {
        const double r = U(rng), re = U(rng), im = 0.01 + std::fabs(U(rng));
        // (t - r)(t^2 - 2 re t + re^2 + im^2)
        const double q1 = -2.0 * re, q0 = re * re + im * im;
        double x[3];
        const int n = solve_cubic(1.0, q1 - r, q0 - r * q1, -r * q0, x);
        REQUIRE(n == 1);
        REQUIRE(close_rel(x[0], r, 1e-9));
    }
}

TEST_CASE("cubic: double and triple roots", "[exact]") {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> U(-10.0, 10.0);
    for (int trial = 0; trial < 20000; ++trial) {
        double a = U(rng), b = U(rng);
        if (std::fabs(a - b) < 1e-2) continue;
        // double root a, simple root b
        const auto k = from_roots(a, a, b);
        double x[3];
        const int n = solve_cubic(k[0], k[1], k[2], k[3], x);
        REQUIRE(n == 3);  // multiplicity is reported
        double want[3] = {a, a, b};
        std::sort(want, want + 3);
        for (int i = 0; i < 3; ++i) {
            INFO("double " << a << " simple " << b << " got " << x[0] << " " << x[1] << " " << x[2]);
            REQUIRE(close_rel(x[i], want[i], 1e-6));
        }
    }
    for (int trial = 0; trial < 20000; ++trial) {
        const double a = U(rng);
        const auto k = from_roots(a, a, a);
        double x[3];
        const int n = solve_cubic(k[0], k[1], k[2], k[3], x);
        REQUIRE(n >= 1);
        for (int i = 0; i < n; ++i) {
            INFO("triple " << a << " got " << x[i]);
            REQUIRE(close_rel(x[i], a, 1e-4));
        }
    }
    double x[3];
    REQUIRE(solve_cubic(1, 0, 0, 0, x) == 3);  // t^3: exact triple root at 0
    REQUIRE((x[0] == 0.0 && x[1] == 0.0 && x[2] == 0.0));
}

TEST_CASE("cubic: degenerate leading coefficients", "[exact]") {
    double x[3];
    SECTION("a = 0: quadratic, including the cancellation-prone case") {
        // (t - 1e-8)(t - 1e8) = t^2 - (1e8 + 1e-8) t + 1: naive formula loses the small root
        REQUIRE(solve_cubic(0.0, 1.0, -(1e8 + 1e-8), 1.0, x) == 2);
        REQUIRE(std::fabs(x[0] - 1e-8) <= 1e-8 * 1e-12);  // relative accuracy of the small root
        REQUIRE(close_rel(x[1], 1e8, 1e-12));
        REQUIRE(solve_cubic(0.0, 2.0, -6.0, 4.0, x) == 2);  // 2(t-1)(t-2)
        REQUIRE(x[0] == Approx(1.0).epsilon(1e-15));
        REQUIRE(x[1] == Approx(2.0).epsilon(1e-15));
        REQUIRE(solve_cubic(0.0, 1.0, 0.0, 1.0, x) == 0);  // t^2 + 1
        REQUIRE(solve_cubic(0.0, 1.0, -2.0, 1.0, x) == 2);  // (t-1)^2
        REQUIRE(x[0] == Approx(1.0));
        REQUIRE(x[1] == Approx(1.0));
    }
    SECTION("a ~ 0 relative to the rest (below the 1e-12 tolerance): quadratic roots kept") {
        REQUIRE(solve_cubic(1e-14, 2.0, -6.0, 4.0, x) == 2);
        REQUIRE(x[0] == Approx(1.0).epsilon(1e-12));
        REQUIRE(x[1] == Approx(2.0).epsilon(1e-12));
    }
    SECTION("a = b = 0: linear") {
        REQUIRE(solve_cubic(0.0, 0.0, 4.0, -2.0, x) == 1);
        REQUIRE(x[0] == 0.5);
        REQUIRE(solve_cubic(1e-15, -1e-14, 4.0, -2.0, x) == 1);
        REQUIRE(x[0] == Approx(0.5).epsilon(1e-12));
    }
    SECTION("a = b = c = 0 with d != 0, and all zero: no roots") {
        REQUIRE(solve_cubic(0.0, 0.0, 0.0, 3.0, x) == 0);
        REQUIRE(solve_cubic(0.0, 0.0, 0.0, 0.0, x) == 0);
    }
}

TEST_CASE("cubic: roots invariant under 1e-12 and 1e12 coefficient scaling", "[exact]") {
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> U(-10.0, 10.0);
    for (double s : {1e-12, 1e12, 1e-200, 1e200}) {
        for (int trial = 0; trial < 5000; ++trial) {
            double r[3] = {U(rng), U(rng), U(rng)};
            std::sort(r, r + 3);
            if (r[1] - r[0] < 1e-3 || r[2] - r[1] < 1e-3) continue;
            const auto k = from_roots(r[0], r[1], r[2], s);
            double x[3];
            REQUIRE(solve_cubic(k[0], k[1], k[2], k[3], x) == 3);
            for (int i = 0; i < 3; ++i) REQUIRE(close_rel(x[i], r[i], 1e-9));
        }
        double x[3];  // quadratic and linear fallbacks scale too
        REQUIRE(solve_cubic(0.0, 2.0 * s, -6.0 * s, 4.0 * s, x) == 2);
        REQUIRE(x[0] == Approx(1.0));
        REQUIRE(x[1] == Approx(2.0));
        REQUIRE(solve_cubic(0.0, 0.0, 4.0 * s, -2.0 * s, x) == 1);
        REQUIRE(x[0] == Approx(0.5));
    }
}

TEST_CASE("cubic: agrees with brute-force bisection on random cubics", "[exact]") {
    std::mt19937_64 rng(31337);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    int compared = 0, skipped = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::array<double, 4> k{U(rng), U(rng), U(rng), U(rng)};
        if (std::fabs(k[0]) < 0.1) k[0] = std::copysign(0.1, k[0]);
        // Cauchy bound on the roots
        const double R = 1.0 + std::max({std::fabs(k[1]), std::fabs(k[2]), std::fabs(k[3])}) / std::fabs(k[0]);
        double x[3];
        const int n = solve_cubic(k[0], k[1], k[2], k[3], x);
        // the grid scan cannot see root pairs closer than a grid step or tangencies; skip those
        const int grid = 20000;
        const double h = 2.0 * R / grid;
        bool close_pair = false;
        for (int i = 0; i + 1 < n; ++i) close_pair |= (x[i + 1] - x[i] < 4.0 * h);
        if (close_pair) { ++skipped; continue; }
        const auto b = bisection_roots(k, R + h, grid);
        INFO("cubic " << k[0] << " " << k[1] << " " << k[2] << " " << k[3]);
        REQUIRE(int(b.size()) == n);
        for (int i = 0; i < n; ++i) REQUIRE(close_rel(x[i], b[i], 1e-9));
        ++compared;
    }
    INFO("compared " << compared << " skipped " << skipped);
    REQUIRE(compared > 2900);
}
