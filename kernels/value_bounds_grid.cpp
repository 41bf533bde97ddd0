#include "kernels/value_bounds_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
constexpr std::int64_t kMaxBoxes = std::int64_t{1} << 27;
}

ValueBoundsGrid value_bounds_from_blocks(const BlockMinMax& b, const GridSpec& g) {
    ValueBoundsGrid out;
    out.origin = {g.origin[0], g.origin[1], g.origin[2]};
    out.cell = {b.edge * g.spacing[0], b.edge * g.spacing[1], b.edge * g.spacing[2]};
    out.dims = b.blocks;
    out.vmin = b.vmin;
    out.vmax = b.vmax;
    // A block without a finite sample: its cells are NaN, which the transfer function maps to
    // transparent; +inf/-inf make the interval empty, which max_opacity reads as 0 at the ends.
    for (std::size_t i = 0; i < out.vmin.size(); ++i)
        if (std::isnan(out.vmin[i]) || std::isnan(out.vmax[i])) {
            out.vmin[i] = std::numeric_limits<double>::infinity();
            out.vmax[i] = -std::numeric_limits<double>::infinity();
        }
    return out;
}

ValueBoundsGrid value_bounds_from_points(std::span<const Vec3> pos, std::span<const double> value, const std::array<Vec3, 2>& box,
                                         double cell_edge, double pad, double margin) {
    if (!(pad >= 0) || !(margin >= 0)) throw InvalidArgument("value bounds: pad and margin must be >= 0");
    ValueBoundsGrid out = empty_point_bounds(box, cell_edge);
    add_point_bounds(out, pos, value, pad);
    widen_point_bounds(out, margin);
    return out;
}

ValueBoundsGrid empty_point_bounds(const std::array<Vec3, 2>& box, double cell_edge) {
    if (!(cell_edge > 0) || !std::isfinite(cell_edge)) throw InvalidArgument("value bounds: macro-cell edge must be positive");
    ValueBoundsGrid out;
    out.origin = box[0];
    out.cell = {cell_edge, cell_edge, cell_edge};
    double total = 1;
    for (int a = 0; a < 3; ++a) {
        const double n = std::max(1.0, std::ceil((box[1][a] - box[0][a]) / cell_edge));
        total *= n;
        if (!(total <= static_cast<double>(kMaxBoxes)))
            throw InvalidArgument("value bounds: more than 2^27 macro cells (edge " + std::to_string(cell_edge) + ")");
        out.dims[a] = static_cast<std::int64_t>(n);
    }
    const auto count = static_cast<std::size_t>(out.count());
    out.vmin.assign(count, std::numeric_limits<double>::infinity());
    out.vmax.assign(count, -std::numeric_limits<double>::infinity());
    return out;
}

void add_point_bounds(ValueBoundsGrid& out, std::span<const Vec3> pos, std::span<const double> value, double pad) {
    if (!(pad >= 0)) throw InvalidArgument("value bounds: pad and margin must be >= 0");
    const double cell_edge = out.cell[0];
    for (std::size_t n = 0; n < pos.size() && n < value.size(); ++n) {
        const double v = value[n];
        if (!std::isfinite(v)) continue;
        std::int64_t lo[3], hi[3];
        bool ok = true;
        for (int a = 0; a < 3; ++a) {
            const double u0 = (pos[n][a] - pad - out.origin[a]) / cell_edge, u1 = (pos[n][a] + pad - out.origin[a]) / cell_edge;
            if (!std::isfinite(u0) || !std::isfinite(u1)) ok = false;
            lo[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(std::max(u0, -1.0))), 0, out.dims[a] - 1);
            hi[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(std::min(u1, static_cast<double>(out.dims[a])))), 0,
                                             out.dims[a] - 1);
        }
        if (!ok) continue;
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
            for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
                for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
                    const auto c = static_cast<std::size_t>(out.index(i, j, k));
                    out.vmin[c] = std::min(out.vmin[c], v);
                    out.vmax[c] = std::max(out.vmax[c], v);
                }
    }
}

void widen_point_bounds(ValueBoundsGrid& out, double margin) {
    if (!(margin >= 0)) throw InvalidArgument("value bounds: pad and margin must be >= 0");
    for (std::size_t c = 0; c < out.vmin.size(); ++c) {
        if (out.vmin[c] > out.vmax[c]) continue;  // no point within pad: no data (the empty interval)
        out.vmin[c] -= margin;
        out.vmax[c] += margin;
    }
}

}  // namespace meshless
