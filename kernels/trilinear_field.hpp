// The trilinear interpolant of a regular grid as a Field (dissertation Eq. 3.1): value and analytic
// gradient of the cell containing each point. Outside the grid, points are clamped to the nearest
// cell's polynomial (extrapolation). Cells with a NaN corner give NaN. The view must outlive the
// field. Thread-safe (const).
#pragma once
#include "kernels/field.hpp"
#include "kernels/grid.hpp"

namespace meshless {

class TrilinearField final : public Field {
public:
    explicit TrilinearField(VolumeView v);
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override;
    std::array<Vec3, 2> bounds() const override;
    std::string name() const override { return "trilinear"; }

private:
    VolumeView v_;
};

}  // namespace meshless
