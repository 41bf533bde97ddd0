#include "ooc/brick_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/errors.hpp"
#include "kernels/trilinear.hpp"

namespace meshless {

BrickStoreField::BrickStoreField(const BrickStore& store, BrickCache& cache) : store_(store), cache_(cache) {
    const auto& n = store.info().bricks_per_axis;
    by_coord_.assign(static_cast<std::size_t>(n[0] * n[1] * n[2]), std::numeric_limits<std::size_t>::max());
    for (std::size_t i = 0; i < store.bricks().size(); ++i) {
        const auto& c = store.bricks()[i].coord;
        by_coord_[static_cast<std::size_t>(c[0] + n[0] * (c[1] + n[1] * static_cast<std::int64_t>(c[2])))] = i;
    }
    for (std::size_t v : by_coord_)
        if (v == std::numeric_limits<std::size_t>::max()) throw FormatError(store.path() + ": the index lacks bricks of the grid");
}

std::array<Vec3, 2> BrickStoreField::bounds() const {
    const GridSpec& g = store_.info().grid;
    return {Vec3{g.origin[0], g.origin[1], g.origin[2]},
            Vec3{g.origin[0] + (g.dims[0] - 1) * g.spacing[0], g.origin[1] + (g.dims[1] - 1) * g.spacing[1],
                 g.origin[2] + (g.dims[2] - 1) * g.spacing[2]}};
}

void BrickStoreField::evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const {
    const BrickStoreInfo& info = store_.info();
    const GridSpec& g = info.grid;
    const std::int64_t B = info.brick_edge;
    std::size_t current = std::numeric_limits<std::size_t>::max();
    std::shared_ptr<const std::vector<std::byte>> bytes;
    VolumeView view;
    std::array<std::int64_t, 3> first{0, 0, 0};
    for (std::size_t n = 0; n < p.size(); ++n) {
        std::int64_t cell[3], bc[3];
        double local[3];
        for (int a = 0; a < 3; ++a) {
            const double u = (p[n][a] - g.origin[a]) / g.spacing[a];
            const std::int64_t last = std::max<std::int64_t>(0, g.dims[a] - 2);
            const double fu = std::floor(u);
            cell[a] = fu != fu ? 0 : fu < 0 ? 0 : fu > static_cast<double>(last) ? last : static_cast<std::int64_t>(fu);
            local[a] = u - static_cast<double>(cell[a]);
            bc[a] = std::min(cell[a] / B, info.bricks_per_axis[a] - 1);
        }
        const std::size_t b =
            by_coord_[static_cast<std::size_t>(bc[0] + info.bricks_per_axis[0] * (bc[1] + info.bricks_per_axis[1] * bc[2]))];
        if (b != current) {
            bytes = cache_.get(b);
            view = cache_.view(b, *bytes);
            first = store_.brick_first_voxel(b);
            current = b;
        }
        double c[8];
        visit_samples(view, [&](auto* data) {
            for (int k = 0; k < 8; ++k) {
                // the brick's far layer: min() keeps a one-sample axis inside
                const std::int64_t i = std::min(cell[0] + (k & 1) - first[0], view.grid.dims[0] - 1);
                const std::int64_t j = std::min(cell[1] + ((k >> 1) & 1) - first[1], view.grid.dims[1] - 1);
                const std::int64_t l = std::min(cell[2] + ((k >> 2) & 1) - first[2], view.grid.dims[2] - 1);
                c[k] = static_cast<double>(data[view.grid.index(i, j, l)]);
            }
        });
        const ValueGrad vg = trilinear(c, local[0], local[1], local[2]);
        value[n] = vg.value;
        if (!grad.empty()) grad[n] = to_world_gradient(vg.grad, Vec3{g.spacing[0], g.spacing[1], g.spacing[2]});
    }
}

ValueBoundsGrid store_value_bounds(const BrickStore& store) {
    const BrickStoreInfo& info = store.info();
    ValueBoundsGrid out;
    const GridSpec& g = info.grid;
    out.origin = {g.origin[0], g.origin[1], g.origin[2]};
    out.cell = {info.brick_edge * g.spacing[0], info.brick_edge * g.spacing[1], info.brick_edge * g.spacing[2]};
    out.dims = info.bricks_per_axis;
    out.vmin.assign(static_cast<std::size_t>(out.count()), std::numeric_limits<double>::quiet_NaN());
    out.vmax = out.vmin;
    for (const BrickEntry& e : store.bricks()) {
        const auto c = static_cast<std::size_t>(out.index(e.coord[0], e.coord[1], e.coord[2]));
        if (c >= out.vmin.size()) continue;
        if (std::isnan(e.vmin) || std::isnan(e.vmax)) {  // no finite sample: NaN values are transparent
            out.vmin[c] = std::numeric_limits<double>::infinity();
            out.vmax[c] = -std::numeric_limits<double>::infinity();
        } else {
            out.vmin[c] = e.vmin;
            out.vmax[c] = e.vmax;
        }
    }
    return out;
}

}  // namespace meshless
