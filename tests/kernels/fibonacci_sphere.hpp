// Splat test points on the unit sphere (Fibonacci lattice), shared by the splat colour tests of
// kernels/ and stream/.
#pragma once
#include <cmath>
#include <numbers>

#include "kernels/records.hpp"
#include "kernels/vec3.hpp"

namespace meshless::test {

/// A point of the sphere: the record (position = normal, radius 2.2 / sqrt(n), value = value_scale * z)
/// and its double-precision position.
struct SpherePoint {
    PointRecord rec;
    Vec3 at;
};

/// Point i (0 <= i < n) of n points on the unit sphere, Fibonacci lattice.
inline SpherePoint fibonacci_sphere_point(int i, int n, double value_scale = 1) {
    const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
    const double z = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - z * z), phi = golden * i;
    PointRecord p{};
    const double x = r * std::cos(phi), y = r * std::sin(phi);
    p.pos[0] = p.normal[0] = static_cast<float>(x);
    p.pos[1] = p.normal[1] = static_cast<float>(y);
    p.pos[2] = p.normal[2] = static_cast<float>(z);
    p.radius = static_cast<float>(2.2 / std::sqrt(n));
    p.value = static_cast<float>(value_scale * z);
    return {p, Vec3{x, y, z}};
}

}  // namespace meshless::test
