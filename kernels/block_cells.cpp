#include "kernels/block_cells.hpp"

#include <algorithm>
#include <cmath>

namespace meshless {

std::int64_t block_cell_count(const StructuredBlock& b) {
    std::int64_t n = 1;
    for (int a = 0; a < 3; ++a) n *= std::max<std::int64_t>(0, b.dims[static_cast<std::size_t>(a)] - 1);
    return n;
}

bool gather_block_cell(const StructuredBlock& b, std::int64_t i, std::int64_t j, std::int64_t k, HexCell& cell,
                       std::array<std::int64_t, 8>& node) {
    for (int c = 0; c < 8; ++c) {
        const std::int64_t n = b.index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        if (!b.is_valid(n)) return false;
        const Vec3& p = b.node[static_cast<std::size_t>(n)];
        const double v = b.value[static_cast<std::size_t>(n)];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(v))) return false;
        cell.corner[static_cast<std::size_t>(c)] = p;
        cell.value[static_cast<std::size_t>(c)] = v;
        node[static_cast<std::size_t>(c)] = n;
    }
    return true;
}

int hex_jacobian_sign(const HexCell& cell) {
    const auto [lo, hi] = hex_jacobian_range(cell.corner);
    if (lo > 0) return 1;
    if (hi < 0) return -1;
    return 0;
}

BlockOrientation block_orientation(const StructuredBlock& b) { return block_orientation(b, 0, b.dims[2]); }

BlockOrientation block_orientation(const StructuredBlock& b, std::int64_t k0, std::int64_t k1) {
    BlockOrientation o;
    if (b.dims[0] < 2 || b.dims[1] < 2 || b.dims[2] < 2) return o;
    k0 = std::max<std::int64_t>(k0, 0);
    k1 = std::min<std::int64_t>(k1, b.dims[2] - 1);
    HexCell cell;
    std::array<std::int64_t, 8> node{};
    for (std::int64_t k = k0; k < k1; ++k)
        for (std::int64_t j = 0; j + 1 < b.dims[1]; ++j)
            for (std::int64_t i = 0; i + 1 < b.dims[0]; ++i) {
                if (!gather_block_cell(b, i, j, k, cell, node)) {
                    ++o.invalid;
                    continue;
                }
                const int s = hex_jacobian_sign(cell);
                (s > 0 ? o.positive : s < 0 ? o.negative : o.degenerate) += 1;
            }
    return o;
}

}  // namespace meshless
