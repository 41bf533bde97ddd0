// Scattered test sets with known isosurfaces (the accuracy benchmark, dissertation chapter 5):
// an analytic field of kernels/analytic_volumes.hpp (sphere, torus, gyroid, Marschner-Lobb) sampled
// at N scattered positions in the world cube [-1,1]^3 in one of three distributions:
//   uniform    positions uniform in the cube;
//   clustered  Gaussian blobs on a uniform background, density contrast 100:1: positions drawn by
//              rejection from the density rho(x) = 1 + 99 max_k exp(-|x - c_k|^2 / (2 sigma^2)),
//              kClusterCount centres c_k uniform in [-0.7, 0.7]^3 (drawn from the seed first),
//              sigma = kClusterSigma, so the densest places hold 100 times the points per volume of
//              the background (most points lie in the blobs: about 90% at the default sigma);
//   layered    sensor casts: dense in x, y, sparse in z: L = layered_layer_count(N) horizontal layers
//              at z_l = -1 + 2 l / (L - 1), each point in a layer drawn uniformly, x, y uniform in
//              [-1, 1], z = z_l plus a jitter uniform in +-kLayerJitter of the layer spacing (clamped
//              to the cube): the spacing within a layer is about 8 to 11 times finer than between
//              layers at 10^4..10^6 points.
// Values: analytic_value(field, position) exactly (no noise). SplitMix64 (kernels/splitmix.hpp)
// seeded by `seed`: the same spec gives the same bytes on every platform. The PointSet has one block
// named after the spec ("sphere-uniform-10000") and value_name "value".
// Throws InvalidArgument when count is 0 or above kMaxScatteredCount. Pure, reentrant.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "kernels/analytic_volumes.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

enum class ScatterDistribution { uniform, clustered, layered };

inline constexpr int kClusterCount = 8;
inline constexpr double kClusterSigma = 0.12;
inline constexpr double kClusterContrast = 100.0;
inline constexpr double kLayerJitter = 0.02;
inline constexpr std::size_t kMaxScatteredCount = std::size_t{1} << 28;

struct ScatteredSetSpec {
    AnalyticField field = AnalyticField::sphere;
    ScatterDistribution distribution = ScatterDistribution::uniform;
    std::size_t count = 10000;
    std::uint64_t seed = 1;
};

PointSet make_scattered_set(const ScatteredSetSpec& spec);

/// Layers of the layered distribution for n points: max(4, round(cbrt(n) / 4)).
int layered_layer_count(std::size_t n);
/// The blob centres of the clustered distribution for `seed` (the first draws of its generator).
std::array<Vec3, kClusterCount> cluster_centres(std::uint64_t seed);
/// The clustered distribution's (unnormalised) density at x: 1 on the background, 100 at a centre.
double clustered_density(const std::array<Vec3, kClusterCount>& centres, const Vec3& x);

/// "uniform", "clustered", "layered".
const char* to_string(ScatterDistribution d);
std::optional<ScatterDistribution> parse_scatter_distribution(std::string_view name);
/// "FIELD-DISTRIBUTION-COUNT", e.g. "gyroid-layered-100000".
std::string scattered_set_name(const ScatteredSetSpec& spec);

}  // namespace meshless
