// Exact ray-trilinear projection (section 3.3.1). See exact_projection.hpp.
#include "kernels/exact_projection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/cubic_solver.hpp"
#include "kernels/trilinear.hpp"

namespace meshless {

std::array<double, 4> trilinear_ray_cubic(const double c[8], const Vec3& p, const Vec3& dir, double iso) {
    // f = k0 + kx x + ky y + kz z + kxy xy + kxz xz + kyz yz + kxyz xyz  (Eq. 3.1 monomial form)
    const double kxy = c[3] - c[2] - c[1] + c[0];
    const double kxz = c[5] - c[4] - c[1] + c[0];
    const double kyz = c[6] - c[4] - c[2] + c[0];
    const double kxyz = c[7] - c[6] - c[5] - c[3] + c[4] + c[2] + c[1] - c[0];
    const ValueGrad vg = trilinear(c, p.x, p.y, p.z);
    const double A = kxyz * dir.x * dir.y * dir.z;
    const double B = kxy * dir.x * dir.y + kxz * dir.x * dir.z + kyz * dir.y * dir.z +
                     kxyz * (dir.x * dir.y * p.z + dir.x * p.y * dir.z + p.x * dir.y * dir.z);
    const double C = dot(vg.grad, dir);  // first-order term: directional derivative at p
    const double D = vg.value - iso;
    return {A, B, C, D};
}

namespace {

Vec3 clamp01(const Vec3& x) {
    return {std::clamp(x.x, 0.0, 1.0), std::clamp(x.y, 0.0, 1.0), std::clamp(x.z, 0.0, 1.0)};
}

// Root of the cubic k in [lo, hi], where k(lo) and k(hi) differ in sign and k is monotone:
// safeguarded Newton (falls back to bisection whenever a step leaves the bracket).
double bracketed_root(const std::array<double, 4>& k, double lo, double hi, double start) {
    double flo = cubic_value(k, lo);
    double t = (start > lo && start < hi) ? start : 0.5 * (lo + hi);
    for (int it = 0; it < 100; ++it) {
        const double f = cubic_value(k, t);
        if (f == 0.0) return t;
        if ((f < 0) == (flo < 0)) { lo = t; flo = f; } else { hi = t; }
        const double fp = (3.0 * k[0] * t + 2.0 * k[1]) * t + k[2];
        double tn = fp != 0.0 ? t - f / fp : 0.5 * (lo + hi);
        if (!(tn > lo && tn < hi)) tn = 0.5 * (lo + hi);
        if (std::fabs(tn - t) <= 1e-15 * (1.0 + std::fabs(t)) || hi - lo <= 1e-15 * (1.0 + std::fabs(t))) return tn;
        t = tn;
    }
    return t;
}

// Smallest |t| root of the ray cubic whose point is inside the cell (within tol); false if none.
// Cardan's closed form (solve_cubic) gives the starting guesses; the roots are then isolated on the ray's parameter interval inside the cell, split at the critical points
// of the cubic, so that each piece is monotone and holds at most one root. This stays accurate when
// the cubic's leading coefficient is tiny and its other roots are far outside the cell, where
// closed-form roots lose all precision.
bool nearest_hit(const double c[8], const Vec3& p, const Vec3& dir, double iso, double tol, double& t_best) {
    const auto k = trilinear_ray_cubic(c, p, dir, iso);
    double t0 = -std::numeric_limits<double>::infinity(), t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        const double pa = p[a], da = dir[a];
        if (da == 0.0) {
            if (pa < -tol || pa > 1.0 + tol) return false;
            continue;
        }
        const double ta = (-tol - pa) / da, tb = (1.0 + tol - pa) / da;
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    if (!(t0 <= t1)) return false;
    double cuts[4] = {t0, 0, 0, 0};
    int ncuts = 1;
    double crit[2];
    const int nc = solve_quadratic(3.0 * k[0], 2.0 * k[1], k[2], crit);
    for (int i = 0; i < nc; ++i)
        if (crit[i] > t0 && crit[i] < t1) cuts[ncuts++] = crit[i];
    cuts[ncuts++] = t1;
    // solve_quadratic returns ascending roots, all strictly inside (t0, t1): cuts is sorted.
    double cardan[3];
    const int nr = solve_cubic(k[0], k[1], k[2], k[3], cardan);
    bool found = false;
    for (int i = 0; i + 1 < ncuts; ++i) {
        const double lo = cuts[i], hi = cuts[i + 1];
        const double flo = cubic_value(k, lo), fhi = cubic_value(k, hi);
        double t;
        if (flo == 0.0) t = lo;
        else if (fhi == 0.0) t = hi;
        else if ((flo < 0) != (fhi < 0)) {
            double start = 0.5 * (lo + hi);
            for (int r = 0; r < nr; ++r)
                if (cardan[r] > lo && cardan[r] < hi) start = cardan[r];
            t = bracketed_root(k, lo, hi, start);
        } else continue;
        if (!found || std::fabs(t) < std::fabs(t_best)) {
            t_best = t;
            found = true;
        }
    }
    return found;
}

}  // namespace

ExactResult exact_project_cell(const double c[8], const Vec3& p, double iso, const ExactParams& params) {
    const ValueGrad vg = trilinear(c, p.x, p.y, p.z);
    if (vg.value == iso) return {p, ExactStatus::ok, 0};
    const double tol = params.inside_tol;

    // 1) gradient ray (unit direction, so |t| is a local distance)
    const Vec3 g = normalized(vg.grad);
    if (dot(g, g) > 0.0) {
        double t = 0.0;
        if (nearest_hit(c, p, g, iso, tol, t)) return {clamp01(p + g * t), ExactStatus::ok, 0};
    }

    // 2) rays towards the corners on the other side of iso (marching-cubes classification)
    const bool p_above = vg.value >= iso;
    double best_dist = std::numeric_limits<double>::infinity();
    ExactResult best{p, ExactStatus::missed, 0};
    for (int i = 0; i < 8; ++i) {
        if ((c[i] >= iso) == p_above) continue;
        const Vec3 corner{double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)};
        const Vec3 dir = corner - p;
        const double len = norm(dir);
        if (!(len > 0.0)) continue;
        double t = 0.0;
        if (!nearest_hit(c, p, dir, iso, tol, t)) continue;
        const double dist = std::fabs(t) * len;
        if (dist < best_dist) {
            best_dist = dist;
            best = {clamp01(p + dir * t), ExactStatus::ok, i + 1};
        }
    }
    return best;
}

}  // namespace meshless
