// Analytic structured blocks for the multiblock tests (marching cubes, seeds, seed graph): a block from
// any node map, and Cartesian lattices (origin + index * spacing, computed the same way in every
// block, so nodes on a shared plane are bitwise equal) sampling an analytic field.
#pragma once
#include <array>
#include <cmath>
#include <functional>
#include <string>

#include "kernels/structured_block.hpp"

namespace meshless::test {

inline double sphere_field(const Vec3& p) { return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z); }

/// Node map of a block: node (i, j, k) (indices as doubles) -> position.
using BlockMap = std::function<Vec3(double, double, double)>;
/// Scalar field sampled at the nodes.
using ScalarFn = std::function<double(const Vec3&)>;

/// Block of dims nodes (i fastest), node (i, j, k) at map(i, j, k), value f(position).
inline StructuredBlock mapped_block(std::array<std::int64_t, 3> dims, const BlockMap& map, const ScalarFn& f,
                                    const std::string& name = {}) {
    StructuredBlock b;
    b.name = name;
    b.dims = dims;
    for (std::int64_t k = 0; k < dims[2]; ++k)
        for (std::int64_t j = 0; j < dims[1]; ++j)
            for (std::int64_t i = 0; i < dims[0]; ++i) {
                const Vec3 p = map(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
                b.node.push_back(p);
                b.value.push_back(f(p));
            }
    return b;
}

/// Block of nodes origin + (i, j, k) * spacing; flip_i reverses the i order (a left-handed block).
inline StructuredBlock lattice_block(const std::string& name, std::array<std::int64_t, 3> dims, Vec3 origin, Vec3 spacing,
                                     const ScalarFn& f, bool flip_i = false) {
    const double last_i = static_cast<double>(dims[0] - 1);
    return mapped_block(
        dims,
        [=](double i, double j, double k) {
            const double ii = flip_i ? last_i - i : i;
            return Vec3{origin.x + ii * spacing.x, origin.y + j * spacing.y, origin.z + k * spacing.z};
        },
        f, name);
}

/// Block of nodes (first + (i, j, k)) * spacing: blocks made with the same spacing have bitwise equal
/// nodes wherever their index ranges overlap.
inline StructuredBlock index_block(const std::string& name, std::array<std::int64_t, 3> first, std::array<std::int64_t, 3> dims,
                                   double h, const ScalarFn& f) {
    const double f0 = static_cast<double>(first[0]), f1 = static_cast<double>(first[1]), f2 = static_cast<double>(first[2]);
    return mapped_block(
        dims, [=](double i, double j, double k) { return Vec3{(f0 + i) * h, (f1 + j) * h, (f2 + k) * h}; }, f, name);
}

/// The sphere |p| = 0.6 sampled on [-1, 1]^3 with n nodes per axis.
inline StructuredBlock sphere_block(std::int64_t n = 21) {
    const double h = 2.0 / static_cast<double>(n - 1);
    return lattice_block("sphere", {n, n, n}, {-1, -1, -1}, {h, h, h}, sphere_field);
}

}  // namespace meshless::test
