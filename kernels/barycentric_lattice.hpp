// The barycentric lattice of samples inside a triangle (dissertation section 4.4: "a uniform lattice
// of samples inside the triangle using barycentric coordinates ... We do not sample along the edge
// of a given triangle ... The number of points sampled inside a triangle is n(n+1)/2").
//
// Rule: for a lattice parameter n >= 1, the samples are the barycentric weights
//   w(i, j, k) = ((i + 1/3), (j + 1/3), (k + 1/3)) / n,   i, j, k >= 0,  i + j + k = n - 1,
// i.e. the centroids of the n(n+1)/2 "upright" sub-triangles of the triangle's n x n subdivision
// (n samples along the u and v directions in the first row, one fewer in each next row). Every
// weight is >= 1/(3n) > 0, so no sample lies on an edge or a corner: two triangles that share an
// edge never produce the same point, and the disc of area A / (n(n+1)/2) around each sample
// (kernels/multiblock_splat_radius.hpp) covers the triangle's area once on average. The weights of
// each sample sum to 1: (i + j + k + 1) / n = n / n.
// n = 1 gives the centroid alone.
// Order: i descending (the first corner's weight largest first), then j descending; deterministic.
// Units: weights are dimensionless. Pure, reentrant; barycentric_lattice allocates its result.
// Throws InvalidArgument when n < 1 or n > kMaxLatticeN.
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

inline constexpr int kMaxLatticeN = 64;

/// n(n+1)/2.
constexpr std::size_t lattice_size(int n) { return static_cast<std::size_t>(n) * static_cast<std::size_t>(n + 1) / 2; }

/// The lattice_size(n) barycentric weights {w0, w1, w2}, in the order documented above.
std::vector<std::array<double, 3>> barycentric_lattice(int n);

/// The point w0 a + w1 b + w2 c.
inline Vec3 barycentric_point(const std::array<double, 3>& w, const Vec3& a, const Vec3& b, const Vec3& c) {
    return a * w[0] + b * w[1] + c * w[2];
}

}  // namespace meshless
