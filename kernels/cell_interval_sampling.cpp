#include "kernels/cell_interval_sampling.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/iso_threshold.hpp"
#include "kernels/trilinear.hpp"

namespace meshless {

CellBox all_cells(const GridSpec& g) {
    CellBox b;
    for (int a = 0; a < 3; ++a) b.hi[a] = std::max<std::int64_t>(g.dims[a] - 1, 0);
    if (b.count() == 0) b.hi = {0, 0, 0};
    return b;
}

double active_threshold(SampleType t, double iso) {
    if (t == SampleType::f32) return static_cast<double>(IsoThreshold<float>(iso).t);
    return std::ceil(iso);
}

namespace {

template <class T>
void sample_box(const T* data, const GridSpec& g, const CellBox& box, const std::array<std::int64_t, 3>& first,
                const std::array<double, 3>& origin, std::vector<CellIntervalSample>& out, CellIntervalStats& stats) {
    constexpr bool is_float = std::is_floating_point_v<T>;
    const std::int64_t nx = g.dims[0], ny = g.dims[1];
    const std::int64_t sy = nx, sz = nx * ny;
    const double sx_w = g.spacing[0], sy_w = g.spacing[1], sz_w = g.spacing[2];
    const Vec3 size{sx_w, sy_w, sz_w};
    for (std::int64_t k = box.lo[2]; k < box.hi[2]; ++k) {
        for (std::int64_t j = box.lo[1]; j < box.hi[1]; ++j) {
            const T* p00 = data + j * sy + k * sz;  // (0, j,   k)
            const T* p10 = p00 + sy;                // (0, j+1, k)
            const T* p01 = p00 + sz;                // (0, j,   k+1)
            const T* p11 = p01 + sy;                // (0, j+1, k+1)
            // the same world coordinates, computed the same way, as kernels/cell_sampling.cpp
            const double lo_y = origin[1] + static_cast<double>(first[1] + j) * sy_w;
            const double lo_z = origin[2] + static_cast<double>(first[2] + k) * sz_w;
            for (std::int64_t i = box.lo[0]; i < box.hi[0]; ++i) {
                const T v[8] = {p00[i], p00[i + 1], p10[i], p10[i + 1], p01[i], p01[i + 1], p11[i], p11[i + 1]};
                if constexpr (is_float) {
                    bool finite = true;
                    for (T x : v) finite = finite && std::isfinite(x);
                    if (!finite) {
                        ++stats.nonfinite_cells;
                        continue;
                    }
                }
                T mn = v[0], mx = v[0];
                for (int a = 1; a < 8; ++a) {
                    mn = std::min(mn, v[a]);
                    mx = std::max(mx, v[a]);
                }
                if (mn == mx) {
                    ++stats.constant_cells;
                    continue;
                }
                double c[8];
                for (int a = 0; a < 8; ++a) c[a] = static_cast<double>(v[a]);
                const ValueGrad vg = trilinear(c, 0.5, 0.5, 0.5);
                const Vec3 gw = to_world_gradient(vg.grad, size);
                const double lo_x = origin[0] + static_cast<double>(first[0] + i) * sx_w;
                CellIntervalSample s;
                s.pos[0] = static_cast<float>(lo_x + 0.5 * sx_w);
                s.pos[1] = static_cast<float>(lo_y + 0.5 * sy_w);
                s.pos[2] = static_cast<float>(lo_z + 0.5 * sz_w);
                s.grad[0] = static_cast<float>(gw.x);
                s.grad[1] = static_cast<float>(gw.y);
                s.grad[2] = static_cast<float>(gw.z);
                s.value = static_cast<float>(vg.value);
                s.vmin = static_cast<float>(mn);
                s.vmax = static_cast<float>(mx);
                out.push_back(s);
                ++stats.samples;
            }
        }
    }
}

}  // namespace

void sample_cell_intervals(const VolumeView& v, const CellBox& box, const std::array<std::int64_t, 3>& first_voxel,
                           const std::array<double, 3>& origin, std::vector<CellIntervalSample>& out,
                           CellIntervalStats& stats) {
    if (box.count() == 0) return;
    visit_samples(v, [&](auto* p) { sample_box(p, v.grid, box, first_voxel, origin, out, stats); });
}

}  // namespace meshless
