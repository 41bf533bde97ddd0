// Analytic structured blocks for the naive multiblock marching cubes tests: Cartesian lattices
// (origin + index * spacing, computed the same way in every block, so nodes on a shared plane are
// bitwise equal) sampling an analytic field.
#pragma once
#include <array>
#include <cmath>
#include <functional>
#include <string>

#include "kernels/structured_block.hpp"

namespace meshless::test {

inline double sphere_field(const Vec3& p) { return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z); }

/// Block of nodes origin + (i, j, k) * spacing; flip_i reverses the i order (a left-handed block).
inline StructuredBlock lattice_block(const std::string& name, std::array<std::int64_t, 3> dims, Vec3 origin, Vec3 spacing,
                                     const std::function<double(const Vec3&)>& f, bool flip_i = false) {
    StructuredBlock b;
    b.name = name;
    b.dims = dims;
    for (std::int64_t k = 0; k < dims[2]; ++k)
        for (std::int64_t j = 0; j < dims[1]; ++j)
            for (std::int64_t i = 0; i < dims[0]; ++i) {
                const std::int64_t ii = flip_i ? dims[0] - 1 - i : i;
                const Vec3 p{origin.x + static_cast<double>(ii) * spacing.x, origin.y + static_cast<double>(j) * spacing.y,
                             origin.z + static_cast<double>(k) * spacing.z};
                b.node.push_back(p);
                b.value.push_back(f(p));
            }
    return b;
}

/// Block of nodes (first + (i, j, k)) * spacing: blocks made with the same spacing have bitwise equal
/// nodes wherever their index ranges overlap.
inline StructuredBlock index_block(const std::string& name, std::array<std::int64_t, 3> first, std::array<std::int64_t, 3> dims,
                                   double h, const std::function<double(const Vec3&)>& f) {
    StructuredBlock b;
    b.name = name;
    b.dims = dims;
    for (std::int64_t k = 0; k < dims[2]; ++k)
        for (std::int64_t j = 0; j < dims[1]; ++j)
            for (std::int64_t i = 0; i < dims[0]; ++i) {
                const Vec3 p{static_cast<double>(first[0] + i) * h, static_cast<double>(first[1] + j) * h,
                             static_cast<double>(first[2] + k) * h};
                b.node.push_back(p);
                b.value.push_back(f(p));
            }
    return b;
}

/// The sphere |p| = 0.6 sampled on [-1, 1]^3 with n nodes per axis.
inline StructuredBlock sphere_block(std::int64_t n = 21) {
    const double h = 2.0 / static_cast<double>(n - 1);
    return lattice_block("sphere", {n, n, n}, {-1, -1, -1}, {h, h, h}, sphere_field);
}

}  // namespace meshless::test
