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

bool inside(const Vec3& x, double tol) {
    return x.x >= -tol && x.x <= 1.0 + tol && x.y >= -tol && x.y <= 1.0 + tol && x.z >= -tol &&
           x.z <= 1.0 + tol;
}

Vec3 clamp01(const Vec3& x) {
    return {std::clamp(x.x, 0.0, 1.0), std::clamp(x.y, 0.0, 1.0), std::clamp(x.z, 0.0, 1.0)};
}

// Smallest |t| root of the ray cubic whose point is inside the cell; returns false when none.
bool nearest_hit(const double c[8], const Vec3& p, const Vec3& dir, double iso, double tol, double& t_best) {
    const auto k = trilinear_ray_cubic(c, p, dir, iso);
    double roots[3];
    const int n = solve_cubic(k[0], k[1], k[2], k[3], roots);
    bool found = false;
    for (int i = 0; i < n; ++i) {
        const double t = roots[i];
        if (found && std::fabs(t) >= std::fabs(t_best)) continue;
        if (!inside(p + dir * t, tol)) continue;
        t_best = t;
        found = true;
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
