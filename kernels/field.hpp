// Field: a continuous scalar function over 3-D space with its gradient, the one interface the
// projection stages take (docs/architecture.md "Core types"), so chapters 3-6 share one projector. Implemented
// by the trilinear grid (kernels/trilinear_field.hpp), the RBF-grid partition of unity (dissertation
// section 4.3), the MPU octree (section 5.5) and Hardy's global interpolant (section 2.1.1).
// Immutable after construction; evaluate() is thread-safe and batch-oriented (one virtual call per
// batch). Units: world coordinates in, values in the data's units, gradients per world unit.
// Outside its domain (bounds()) a field may extrapolate or return NaN; each implementation says.
#pragma once
#include <array>
#include <span>
#include <string>

#include "kernels/vec3.hpp"

namespace meshless {

class Field {
public:
    virtual ~Field() = default;
    /// value[i] (and grad[i] when grad is not empty) at p[i]. Preconditions: value.size() ==
    /// p.size(), grad.empty() || grad.size() == p.size(). Throws nothing but std::bad_alloc.
    /// Every point's result is independent of the rest of the batch (an implementation may visit a
    /// batch in its own order, e.g. spatially sorted, but writes each result to its own slot), so
    /// callers gain by passing large batches (thousands of points) and lose nothing by any order.
    virtual void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const = 0;
    /// Axis-aligned domain [lo, hi], world units.
    virtual std::array<Vec3, 2> bounds() const = 0;
    /// Short name for messages and metadata ("trilinear", "rbf-grid", "mpu", "global-rbf").
    virtual std::string name() const = 0;

    /// Convenience single-point evaluation.
    double value(const Vec3& p, Vec3* grad = nullptr) const {
        double v = 0;
        Vec3 g;
        evaluate(std::span<const Vec3>(&p, 1), std::span<double>(&v, 1), grad ? std::span<Vec3>(&g, 1) : std::span<Vec3>());
        if (grad) *grad = g;
        return v;
    }
};

}  // namespace meshless
