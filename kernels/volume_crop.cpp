#include "kernels/volume_crop.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "kernels/significant_text.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {
std::string number(double v) { return significant_text(v, 9); }
}  // namespace

VoxelBox crop_voxels(const GridSpec& g, const std::array<double, 6>& world, const std::string& name) {
    static constexpr char kAxis[3] = {'x', 'y', 'z'};
    VoxelBox b;
    for (int a = 0; a < 3; ++a) {
        const double lo = world[a], hi = world[a + 3];
        if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi)
            throw InvalidArgument(name + ": crop along " + kAxis[a] + " from " + number(lo) + " to " + number(hi) +
                                  ": expected finite numbers, the first at most the second");
        // the first and last sample at or inside the box (the same arithmetic as a sample's position)
        const double s = g.spacing[a], o = g.origin[a];
        std::int64_t i0 = static_cast<std::int64_t>(std::max(0.0, std::min(std::ceil((lo - o) / s), static_cast<double>(g.dims[a]))));
        std::int64_t i1 = static_cast<std::int64_t>(std::max(-1.0, std::min(std::floor((hi - o) / s), static_cast<double>(g.dims[a] - 1))));
        while (i0 > 0 && o + static_cast<double>(i0 - 1) * s >= lo) --i0;           // rounding of the division
        while (i0 < g.dims[a] && o + static_cast<double>(i0) * s < lo) ++i0;
        while (i1 + 1 < g.dims[a] && o + static_cast<double>(i1 + 1) * s <= hi) ++i1;
        while (i1 >= 0 && o + static_cast<double>(i1) * s > hi) --i1;
        if (i1 - i0 + 1 < 2)
            throw InvalidArgument(name + ": the crop keeps " + std::to_string(std::max<std::int64_t>(0, i1 - i0 + 1)) + " sample(s) along " +
                                  kAxis[a] + " (the volume spans " + number(o) + " to " +
                                  number(o + static_cast<double>(g.dims[a] - 1) * s) + "): at least 2 are needed");
        b.lo[a] = i0;
        b.hi[a] = i1;
    }
    return b;
}

GridSpec cropped_grid(const GridSpec& g, const VoxelBox& box) {
    GridSpec c = g;
    for (int a = 0; a < 3; ++a) {
        c.dims[a] = box.hi[a] - box.lo[a] + 1;
        c.origin[a] = g.origin[a] + static_cast<double>(box.lo[a]) * g.spacing[a];
    }
    return c;
}

Volume crop_volume(const Volume& v, const VoxelBox& box) {
    Volume c(cropped_grid(v.grid, box), v.type);
    const std::size_t ss = sample_size(v.type);
    const std::size_t row = static_cast<std::size_t>(c.grid.dims[0]) * ss;
    for (std::int64_t k = 0; k < c.grid.dims[2]; ++k)
        for (std::int64_t j = 0; j < c.grid.dims[1]; ++j) {
            const std::size_t from = static_cast<std::size_t>(((box.lo[2] + k) * v.grid.dims[1] + box.lo[1] + j) * v.grid.dims[0] + box.lo[0]);
            std::memcpy(c.bytes.data() + static_cast<std::size_t>(k * c.grid.dims[1] + j) * row, v.bytes.data() + from * ss, row);
        }
    return c;
}

}  // namespace meshless
