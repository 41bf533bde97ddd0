#include "kernels/analytic_volumes.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "kernels/errors.hpp"

namespace meshless {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTorusMajor = 0.5;
constexpr double kGyroidK = 2.0 * kPi;
constexpr double kMlFm = 6.0;
constexpr double kMlAlpha = 0.25;

double ml_rho(double r) { return std::cos(2.0 * kPi * kMlFm * std::cos(kPi * r / 2.0)); }

}  // namespace

double analytic_value(AnalyticField f, const Vec3& p) {
    switch (f) {
        case AnalyticField::sphere: return norm(p);
        case AnalyticField::torus: {
            const double rho = std::hypot(p.x, p.y) - kTorusMajor;
            return std::hypot(rho, p.z);
        }
        case AnalyticField::gyroid: {
            const double x = kGyroidK * p.x, y = kGyroidK * p.y, z = kGyroidK * p.z;
            return std::sin(x) * std::cos(y) + std::sin(y) * std::cos(z) + std::sin(z) * std::cos(x);
        }
        case AnalyticField::marschner_lobb: {
            const double r = std::hypot(p.x, p.y);
            return (1.0 - std::sin(kPi * p.z / 2.0) + kMlAlpha * (1.0 + ml_rho(r))) /
                   (2.0 * (1.0 + kMlAlpha));
        }
    }
    return 0;
}

Vec3 analytic_gradient(AnalyticField f, const Vec3& p) {
    switch (f) {
        case AnalyticField::sphere: return normalized(p);  // 0 at the centre (undefined there)
        case AnalyticField::torus: {
            const double q = std::hypot(p.x, p.y);
            const double rho = q - kTorusMajor;
            const double d = std::hypot(rho, p.z);
            if (d == 0) return {0, 0, 0};
            if (q == 0) return {0, 0, p.z / d};  // on the axis: radial part undefined, symmetric
            return {rho / d * p.x / q, rho / d * p.y / q, p.z / d};
        }
        case AnalyticField::gyroid: {
            const double x = kGyroidK * p.x, y = kGyroidK * p.y, z = kGyroidK * p.z;
            const double sx = std::sin(x), cx = std::cos(x), sy = std::sin(y), cy = std::cos(y),
                         sz = std::sin(z), cz = std::cos(z);
            return Vec3{cx * cy - sz * sx, cy * cz - sx * sy, cz * cx - sy * sz} * kGyroidK;
        }
        case AnalyticField::marschner_lobb: {
            const double r = std::hypot(p.x, p.y);
            const double s = 1.0 / (2.0 * (1.0 + kMlAlpha));
            const double gz = -(kPi / 2.0) * std::cos(kPi * p.z / 2.0) * s;
            if (r == 0) return {0, 0, gz};
            // d rho / d r = sin(2 pi f_M cos(pi r/2)) * 2 pi f_M * sin(pi r/2) * pi/2
            const double drho = std::sin(2.0 * kPi * kMlFm * std::cos(kPi * r / 2.0)) * 2.0 * kPi *
                                kMlFm * std::sin(kPi * r / 2.0) * (kPi / 2.0);
            const double gr = kMlAlpha * drho * s;
            return {gr * p.x / r, gr * p.y / r, gz};
        }
    }
    return {};
}

double analytic_distance(AnalyticField f, double iso, const Vec3& p) {
    switch (f) {
        case AnalyticField::sphere:
        case AnalyticField::torus: return std::abs(analytic_value(f, p) - iso);
        case AnalyticField::gyroid:
        case AnalyticField::marschner_lobb: break;
    }
    const double f0 = analytic_value(f, p) - iso;
    if (f0 == 0) return 0;
    const Vec3 g0 = analytic_gradient(f, p);
    const double g0n = norm(g0);
    const double first_order =
        g0n > 0 ? std::abs(f0) / g0n : std::numeric_limits<double>::infinity();
    // 1-D Newton along the line through p in the gradient direction: phi(s) = f(p + s u) - iso.
    const Vec3 u = g0 * (1.0 / g0n);
    double sv = 0;
    for (int it = 0; it < 20 && g0n > 0; ++it) {
        const Vec3 q = p + u * sv;
        const double fq = analytic_value(f, q) - iso;
        if (std::abs(fq) < 1e-12) return std::abs(sv);
        const double slope = dot(analytic_gradient(f, q), u);
        if (!(std::abs(slope) > 1e-12)) break;
        sv -= fq / slope;
        if (!(std::abs(sv) < 10.0 * first_order + 1e-9)) break;  // wandered off: give up
    }
    return first_order;
}

double default_iso(AnalyticField f) {
    switch (f) {
        case AnalyticField::sphere: return 0.7;
        case AnalyticField::torus: return 0.25;
        case AnalyticField::gyroid: return 0.0;
        case AnalyticField::marschner_lobb: return 0.5;
    }
    return 0;
}

const char* to_string(AnalyticField f) {
    switch (f) {
        case AnalyticField::sphere: return "sphere";
        case AnalyticField::torus: return "torus";
        case AnalyticField::gyroid: return "gyroid";
        case AnalyticField::marschner_lobb: return "ml";
    }
    return "?";
}

std::optional<AnalyticField> parse_analytic_field(std::string_view s) {
    if (s == "sphere") return AnalyticField::sphere;
    if (s == "torus") return AnalyticField::torus;
    if (s == "gyroid") return AnalyticField::gyroid;
    if (s == "ml" || s == "marschner_lobb" || s == "marschner-lobb") return AnalyticField::marschner_lobb;
    return std::nullopt;
}

Volume make_analytic_volume(AnalyticField f, std::int64_t n) {
    if (n < 2 || n > (std::int64_t{1} << 20))
        throw InvalidArgument("analytic volume " + std::string(to_string(f)) + ": grid size " +
                              std::to_string(n) + " out of range, expected 2..1048576");
    GridSpec g;
    g.dims = {n, n, n};
    const double h = 2.0 / static_cast<double>(n - 1);
    g.origin = {-1.0, -1.0, -1.0};
    g.spacing = {h, h, h};
    Volume vol(g, SampleType::f32);
    float* out = reinterpret_cast<float*>(vol.bytes.data());
    for (std::int64_t k = 0; k < n; ++k)
        for (std::int64_t j = 0; j < n; ++j)
            for (std::int64_t i = 0; i < n; ++i) {
                const Vec3 p{-1.0 + h * static_cast<double>(i), -1.0 + h * static_cast<double>(j),
                             -1.0 + h * static_cast<double>(k)};
                out[g.index(i, j, k)] = static_cast<float>(analytic_value(f, p));
            }
    return vol;
}

}  // namespace meshless
