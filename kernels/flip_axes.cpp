#include "kernels/flip_axes.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace meshless {

void flip_axes(Volume& v, const std::array<bool, 3>& flip) {
    if (!flip[0] && !flip[1] && !flip[2]) return;
    const std::size_t es = sample_size(v.type);
    const auto nx = static_cast<std::size_t>(v.grid.dims[0]), ny = static_cast<std::size_t>(v.grid.dims[1]),
               nz = static_cast<std::size_t>(v.grid.dims[2]);
    std::byte* p = v.bytes.data();
    const std::size_t row = nx * es, plane = row * ny;
    std::vector<std::byte> tmp(es);
    if (flip[0]) {
        for (std::size_t r = 0; r < ny * nz; ++r) {
            std::byte* a = p + r * row;
            for (std::size_t i = 0, j = nx - 1; i < j; ++i, --j) {
                std::memcpy(tmp.data(), a + i * es, es);
                std::memcpy(a + i * es, a + j * es, es);
                std::memcpy(a + j * es, tmp.data(), es);
            }
        }
    }
    if (flip[1]) {
        for (std::size_t k = 0; k < nz; ++k) {
            std::byte* pl = p + k * plane;
            for (std::size_t i = 0, j = ny - 1; i < j; ++i, --j) std::swap_ranges(pl + i * row, pl + (i + 1) * row, pl + j * row);
        }
    }
    if (flip[2]) {
        for (std::size_t i = 0, j = nz - 1; i < j; ++i, --j) std::swap_ranges(p + i * plane, p + (i + 1) * plane, p + j * plane);
    }
}

void honour_signed_spacing(GridSpec& g, std::array<bool, 3>& flip, int axis, double s) {
    g.spacing[axis] = std::fabs(s);
    if (s < 0) {
        g.origin[axis] += static_cast<double>(g.dims[axis] - 1) * s;
        flip[axis] = true;
    }
}

}  // namespace meshless
