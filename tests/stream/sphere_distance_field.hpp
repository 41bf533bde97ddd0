// |p| as a Field (kernels/field.hpp), evaluated point by point: the sphere of radius iso for any
// iso > 0, gradient p/|p| (0 at the centre, where the projection has no direction). Shared by the
// projection-stage tests of stream/.
#pragma once
#include <array>
#include <span>
#include <string>

#include "kernels/field.hpp"
#include "kernels/vec3.hpp"

namespace meshless::test {

class SphereDistance final : public Field {
public:
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override {
        for (std::size_t i = 0; i < p.size(); ++i) {
            value[i] = norm(p[i]);
            if (!grad.empty()) grad[i] = normalized(p[i]);
        }
    }
    std::array<Vec3, 2> bounds() const override { return {Vec3{-1, -1, -1}, Vec3{1, 1, 1}}; }
    std::string name() const override { return "sphere-distance"; }
};

}  // namespace meshless::test
