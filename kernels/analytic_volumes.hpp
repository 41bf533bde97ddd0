// Analytic scalar fields with known isosurfaces, for tests, the demo and benchmarks (the oracles of
// docs/architecture.md; dissertation §3.6 uses the Marschner–Lobb function and synthetic fields).
//
// Every field is defined on the world cube [-1,1]^3 and sampled by make_analytic_volume(f, n) on an
// n^3 float32 grid with origin (-1,-1,-1) and spacing 2/(n-1) (so a voxel is 2/(n-1) world units;
// divide world distances by grid.spacing[0] to get voxels). The functions below take world
// coordinates and do not depend on n, so one definition serves every resolution.
//   sphere          value = |p| (a distance field),           default iso 0.7  (radius 0.35 (n-1) voxels)
//   torus           value = distance to the core circle of radius 0.5 in the plane z = 0
//                   = sqrt((sqrt(x^2+y^2) - 0.5)^2 + z^2),   default iso 0.25 (the tube radius)
//   gyroid          value = sin(kx)cos(ky) + sin(ky)cos(kz) + sin(kz)cos(kx), k = 2*pi (two periods
//                   across the cube), default iso 0
//   marschner_lobb  Marschner & Lobb 1994, f_M = 6, alpha = 0.25:
//                   value = (1 - sin(pi z/2) + alpha (1 + cos(2 pi f_M cos(pi r/2)))) / (2 (1+alpha)),
//                   r = sqrt(x^2+y^2), range [0,1], default iso 0.5
// analytic_distance: exact for sphere (| |p| - iso |) and torus (|value - iso|, valid for iso < 0.5);
// for gyroid and Marschner–Lobb an ESTIMATE: Newton steps (at most 20, until |f - iso| < 1e-12) on
// the line through p along grad f(p), and the distance to the crossing found; that crossing is a
// surface point, so the estimate is an upper bound of the true distance, close to it for points near
// the surface; where the iteration fails (flat gradient, wandering), the first-order estimate
// |f - iso| / |grad f| (inf where grad f = 0).
// Names: "sphere", "torus", "gyroid", "ml" (parse also accepts "marschner_lobb", "marschner-lobb").
// Throws InvalidArgument from make_analytic_volume when n < 2 or n^3 samples would not fit in memory
// addressing (n > 2^20). Everything else is pure, reentrant and allocation-free.
#pragma once
#include <cstdint>
#include <optional>
#include <string_view>

#include "kernels/grid.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

enum class AnalyticField { sphere, torus, gyroid, marschner_lobb };

struct AnalyticSpec {
    AnalyticField field = AnalyticField::sphere;
    std::int64_t n = 64;  ///< n^3 grid
};

/// n^3 float32 samples of the field over [-1,1]^3 (origin -1, spacing 2/(n-1)).
Volume make_analytic_volume(AnalyticField f, std::int64_t n);
inline Volume make_analytic_volume(const AnalyticSpec& s) { return make_analytic_volume(s.field, s.n); }

/// The continuous function at a world position.
double analytic_value(AnalyticField f, const Vec3& world);
/// Its exact gradient (value per world unit).
Vec3 analytic_gradient(AnalyticField f, const Vec3& world);
/// Distance in world units from `world` to the isosurface value == iso (see the header comment).
double analytic_distance(AnalyticField f, double iso, const Vec3& world);
/// The isosurface value used by default (does not depend on the grid size).
double default_iso(AnalyticField f);

/// "sphere", "torus", "gyroid", "ml".
const char* to_string(AnalyticField f);
std::optional<AnalyticField> parse_analytic_field(std::string_view name);

}  // namespace meshless
