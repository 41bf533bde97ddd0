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
    visit_samples(v_, [&](auto* data) {
        for (std::size_t n = 0; n < p.size(); ++n) {
            std::int64_t cell[3];
            double local[3];
            for (int a = 0; a < 3; ++a) {
                const double u = (p[n][a] - g.origin[a]) / g.spacing[a];
                const std::int64_t last = std::max<std::int64_t>(0, g.dims[a] - 2);
                cell[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(u)), 0, last);
                local[a] = u - static_cast<double>(cell[a]);
            }
            double c[8];
            for (int k = 0; k < 8; ++k) {
                const std::int64_t i = std::min(cell[0] + (k & 1), g.dims[0] - 1);
                const std::int64_t j = std::min(cell[1] + ((k >> 1) & 1), g.dims[1] - 1);
                const std::int64_t l = std::min(cell[2] + ((k >> 2) & 1), g.dims[2] - 1);
                c[k] = static_cast<double>(data[g.index(i, j, l)]);
            }
            const ValueGrad vg = trilinear(c, local[0], local[1], local[2]);
            value[n] = vg.value;
            if (!grad.empty()) grad[n] = to_world_gradient(vg.grad, Vec3{g.spacing[0], g.spacing[1], g.spacing[2]});
        }
    });
}

}  // namespace meshless
