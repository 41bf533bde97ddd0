// Cubic and quadratic root finding (section 3.3.1, Eq. 3.3). See cubic_solver.hpp.
#include "kernels/cubic_solver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace meshless {
namespace {

// Discriminants in [-kDiscTol*scale, 0) are treated as 0 (double root), see header.
constexpr double kDiscTol = 1e-12;

// Quadratic on already-normalised coefficients (max |coef| of the caller ~ 1); no polishing.
// eb, ec: magnitudes of the terms b and c were computed from (|b|, |c| when given directly); their
// rounding error widens the band of negative discriminants read as a double root.
int quadratic_normalised(double a, double b, double c, double r[2], double eb = 0.0, double ec = 0.0) {
    if (std::fabs(a) <= kCubicZeroTol) {
        if (std::fabs(b) <= kCubicZeroTol) return 0;  // constant c (c == 0 only if all were ~0)
        r[0] = -c / b;
        return 1;
    }
    double disc = b * b - 4.0 * a * c;
    const double disc_scale = b * b + std::fabs(4.0 * a * c) + std::fabs(b) * eb + std::fabs(a) * ec;
    if (disc < 0.0) {
        if (disc < -kDiscTol * disc_scale) return 0;
        disc = 0.0;
    }
    // q = -(b + sign(b) sqrt(disc)) / 2 avoids cancellation; roots q/a and c/q.
    const double s = std::sqrt(disc);
    const double q = -0.5 * (b + std::copysign(s, b));
    if (q == 0.0) {  // b == 0 and disc == 0  =>  c == 0: double root at 0
        r[0] = r[1] = 0.0;
        return 2;
    }
    double x0 = q / a, x1 = c / q;
    if (disc == 0.0) x1 = x0;  // exact double root: -b / (2a)
    if (x0 > x1) std::swap(x0, x1);
    r[0] = x0;
    r[1] = x1;
    return 2;
}

// Up to two Newton iterations on the cubic; a step is kept only when it lowers |f|.
double polish(double a, double b, double c, double d, double t) {
    double f = ((a * t + b) * t + c) * t + d;
    for (int it = 0; it < 2 && f != 0.0; ++it) {
        const double fp = (3.0 * a * t + 2.0 * b) * t + c;
        if (fp == 0.0) break;
        const double tn = t - f / fp;
        const double fn = ((a * tn + b) * tn + c) * tn + d;
        if (!(std::fabs(fn) < std::fabs(f))) break;
        t = tn;
        f = fn;
    }
    return t;
}

int finish(double a, double b, double c, double d, double* r, int n) {
    for (int i = 0; i < n; ++i) r[i] = polish(a, b, c, d, r[i]);
    std::sort(r, r + n);
    return n;
}

}  // namespace

int solve_quadratic(double a, double b, double c, double roots[2]) {
    const double s = std::max({std::fabs(a), std::fabs(b), std::fabs(c)});
    if (!(s > 0.0)) return 0;
    return quadratic_normalised(a / s, b / s, c / s, roots);
}

int solve_cubic(double a, double b, double c, double d, double roots[3]) {
    const double s = std::max({std::fabs(a), std::fabs(b), std::fabs(c), std::fabs(d)});
    if (!(s > 0.0)) return 0;  // identically zero polynomial
    a /= s; b /= s; c /= s; d /= s;

    if (std::fabs(a) <= kCubicZeroTol) {
        const int n = quadratic_normalised(b, c, d, roots);
        return finish(a, b, c, d, roots, n);
    }

    // Monic form t^3 + B t^2 + C t + D, depressed by t = x - B/3: x^3 + p x + q = 0.
    const double B = b / a, C = c / a, D = d / a;
    const double shift = B / 3.0;
    const double p = C - B * shift;                               // C - B^2/3
    const double q = (2.0 * shift * shift - C) * shift + D;       // 2B^3/27 - BC/3 + D
    const double h = 0.5 * q, g = p / 3.0;
    const double disc = h * h + g * g * g;  // (q/2)^2 + (p/3)^3

    if (disc <= 0.0) {
        // Three real roots (trigonometric form). disc <= 0 implies p <= 0.
        if (g >= 0.0) {  // p == 0 (and then q == 0): triple root
            roots[0] = roots[1] = roots[2] = -shift;
            return finish(a, b, c, d, roots, 3);
        }
        const double m = std::sqrt(-g);                          // sqrt(-p/3)
        const double cos3 = std::clamp(-h / (m * m * m), -1.0, 1.0);
        const double phi = std::acos(cos3) / 3.0;
        constexpr double k2pi3 = 2.0 * std::numbers::pi / 3.0;
        roots[0] = 2.0 * m * std::cos(phi) - shift;
        roots[1] = 2.0 * m * std::cos(phi - k2pi3) - shift;
        roots[2] = 2.0 * m * std::cos(phi + k2pi3) - shift;
        return finish(a, b, c, d, roots, 3);
    }

    // One real root (Cardan); the cube root of the larger-magnitude term avoids cancellation.
    const double u = std::cbrt(-h - std::copysign(std::sqrt(disc), h));
    const double x = (u != 0.0) ? u - g / u : 0.0;
    double r = polish(a, b, c, d, x - shift);
    // Deflate (t - r)(a t^2 + e t + f): a near-zero discriminant of the remainder is a double root
    // that rounding pushed to disc > 0 above.
    const double e = b + a * r;
    const double f = (r != 0.0 && std::fabs(r) > 1e-8) ? -d / r : c + e * r;
    double rest[2];
    const int n2 = quadratic_normalised(a, e, f, rest, std::fabs(b) + std::fabs(a * r),
                                        std::fabs(c) + std::fabs(e * r));
    roots[0] = r;
    for (int i = 0; i < n2; ++i) roots[1 + i] = rest[i];
    return finish(a, b, c, d, roots, 1 + n2);
}

}  // namespace meshless
