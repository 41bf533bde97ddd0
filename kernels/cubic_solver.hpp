// Real roots of a cubic a t^3 + b t^2 + c t + d = 0 (dissertation section 3.3.1, Eq. 3.3, solved with
// Cardan's solution [Nickalls 1993] and its trigonometric form).
//
// Units: dimensionless; any scaling of (a,b,c,d) gives the same roots (coefficients are first divided by
// s = max(|a|,|b|,|c|,|d|); tested with scalings 1e-200..1e200).
// Degenerate leading coefficients: after that normalisation a coefficient with |x| <= kCubicZeroTol
// (1e-12) is treated as zero: |a| ~ 0 -> quadratic b t^2 + c t + d, |a|,|b| ~ 0 -> linear, all of
// a,b,c ~ 0 (but d != 0) -> no root. Dropping a tiny a discards one root of magnitude roughly
// >= |b|/|a| (or (|d|/|a|)^(1/3)), i.e. far outside any unit cell; the kept roots are still polished on
// the full cubic. The identically zero polynomial (s == 0) returns 0 roots (every t solves it).
// Multiplicity: a double root is returned twice; a triple root comes back three times or, when
// rounding splits it into a real root and a tiny complex pair, once (both within the accuracy below).
// A complex pair whose imaginary part is below ~1e-6 of its real part (relative discriminant > -1e-12)
// is reported as a double real root (a grazing ray touches the surface). Each root is polished with up to 2 Newton iterations on
// the normalised cubic (a step is kept only when it reduces |f|). Roots are sorted ascending.
// Accuracy: well-separated simple roots to ~1e-15 relative; double roots to ~1e-7, triple roots to
// ~2e-5, relative to the largest root (the conditioning of the problem, not of the method).
// Preconditions: finite inputs (NaN/inf give unspecified results). Throws nothing. Pure, reentrant.
#pragma once
#include <array>

namespace meshless {

/// Relative threshold under which a normalised coefficient counts as zero (see header comment).
inline constexpr double kCubicZeroTol = 1e-12;

/// Real roots of a x^2 + b x + c = 0 (stable form, no cancellation), ascending, count 0..2. Same
/// normalisation and zero tolerance as solve_cubic; a ~ 0 falls back to linear.
int solve_quadratic(double a, double b, double c, double roots[2]);

/// Real roots of a t^3 + b t^2 + c t + d = 0, ascending, returns the count (0..3).
int solve_cubic(double a, double b, double c, double d, double roots[3]);

/// Horner evaluation of a t^3 + b t^2 + c t + d with coefficients {a,b,c,d}.
constexpr double cubic_value(const std::array<double, 4>& k, double t) {
    return ((k[0] * t + k[1]) * t + k[2]) * t + k[3];
}

}  // namespace meshless
