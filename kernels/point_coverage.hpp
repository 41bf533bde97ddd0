// Where scattered data actually covers space: a position x is covered when its nearest data point
// p_i lies within factor * h_i, h_i being the distance from p_i to its k-th nearest neighbour (k = 8,
// fewer for tiny sets) — a local spacing that adapts to graded and anisotropic grids. Meshless fields
// extrapolate beyond their data (an RBF grows away from its points); callers that show values to a
// user (probe, slice, resample) mark uncovered positions NaN instead of presenting extrapolation as
// data. kNN via nanoflann (the only file that includes it). Immutable after construction;
// covered() is thread-safe. Throws std::bad_alloc only.
#pragma once
#include <memory>
#include <span>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

class PointCoverage {
public:
    /// factor > 0. The points must outlive nothing: they are copied.
    PointCoverage(std::span<const Vec3> points, double factor);
    ~PointCoverage();
    PointCoverage(const PointCoverage&) = delete;
    PointCoverage& operator=(const PointCoverage&) = delete;
    bool covered(const Vec3& x) const;
    /// Sets value[i] (and grad[i]) to NaN where p[i] is not covered; returns how many.
    std::size_t mask(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace meshless
