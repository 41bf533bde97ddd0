#include "kernels/trilinear_field.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/trilinear.hpp"

namespace meshless {

TrilinearField::TrilinearField(VolumeView v) : v_(v) {}

std::array<Vec3, 2> TrilinearField::bounds() const {
    const GridSpec& g = v_.grid;
    return {Vec3{g.origin[0], g.origin[1], g.origin[2]},
            Vec3{g.origin[0] + (g.dims[0] - 1) * g.spacing[0], g.origin[1] + (g.dims[1] - 1) * g.spacing[1],
                 g.origin[2] + (g.dims[2] - 1) * g.spacing[2]}};
}

void TrilinearField::evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const {
    const GridSpec& g = v_.grid;
    // Hoisted per batch: the last cell per axis, and the corner offsets (an axis
    // of one sample has no second layer: its offset is 0, the same clamp as min(i + 1, n - 1)).
    double org[3];
    std::int64_t last[3], stride[3];
    const std::int64_t s3[3] = {1, g.dims[0], g.dims[0] * g.dims[1]};
    for (int a = 0; a < 3; ++a) {
        org[a] = g.origin[a];
        last[a] = std::max<std::int64_t>(0, g.dims[a] - 2);
        stride[a] = g.dims[a] > 1 ? s3[a] : 0;
    }
    std::int64_t off[8];
    for (int k = 0; k < 8; ++k) off[k] = (k & 1) * stride[0] + ((k >> 1) & 1) * stride[1] + ((k >> 2) & 1) * stride[2];
    const Vec3 spacing{g.spacing[0], g.spacing[1], g.spacing[2]};
    visit_samples(v_, [&](auto* data) {
        for (std::size_t n = 0; n < p.size(); ++n) {
            std::int64_t cell[3];
            double local[3];
            for (int a = 0; a < 3; ++a) {
                // (p - origin) / spacing as in the clamped-cell rule; division kept exact for the
                // values tests compare bit for bit
                const double u = (p[n][a] - org[a]) / g.spacing[a];
                const double f = std::floor(u);
                cell[a] = !(f >= 0) ? 0 : f > static_cast<double>(last[a]) ? last[a] : static_cast<std::int64_t>(f);
                local[a] = u - static_cast<double>(cell[a]);
            }
            const auto* base = data + (cell[0] + s3[1] * cell[1] + s3[2] * cell[2]);
            double c[8];
            for (int k = 0; k < 8; ++k) c[k] = static_cast<double>(base[off[k]]);
            const ValueGrad vg = trilinear(c, local[0], local[1], local[2]);
            value[n] = vg.value;
            if (!grad.empty()) grad[n] = to_world_gradient(vg.grad, spacing);
        }
    });
}

}  // namespace meshless
