#include "kernels/block_marching_cubes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "kernels/hex_marching_cubes.hpp"

namespace meshless {

namespace {

/// Gathers cell (i,j,k); false when a corner is invalid or not finite.
bool gather(const StructuredBlock& b, std::int64_t i, std::int64_t j, std::int64_t k, HexCell& cell,
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

/// +1 / -1 for a one-signed Jacobian, 0 for a collapsed or inverted cell.
int jacobian_sign(const HexCell& cell) {
    const auto [lo, hi] = hex_jacobian_range(cell.corner);
    if (lo > 0) return 1;
    if (hi < 0) return -1;
    return 0;
}

}  // namespace

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
                if (!gather(b, i, j, k, cell, node)) {
                    ++o.invalid;
                    continue;
                }
                const int s = jacobian_sign(cell);
                (s > 0 ? o.positive : s < 0 ? o.negative : o.degenerate) += 1;
            }
    return o;
}

Mesh block_marching_cubes(const StructuredBlock& b, double iso, bool left_handed, std::int64_t k0, std::int64_t k1,
                          std::uint32_t block_id, BlockMcStats& st, std::vector<std::uint64_t>& edge_keys) {
    Mesh m;
    edge_keys.clear();
    if (b.dims[0] < 2 || b.dims[1] < 2 || b.dims[2] < 2) return m;
    k0 = std::max<std::int64_t>(k0, 0);
    k1 = std::min<std::int64_t>(k1, b.dims[2] - 1);
    if (k1 <= k0) return m;
    const McTable& table = marching_cubes_table();
    std::unordered_map<std::uint64_t, std::uint32_t> vertex_of;
    HexCell cell;
    std::array<std::int64_t, 8> node{};
    std::array<HexTriangle, kMcMaxTriangles> tris;
    for (std::int64_t k = k0; k < k1; ++k)
        for (std::int64_t j = 0; j + 1 < b.dims[1]; ++j)
            for (std::int64_t i = 0; i + 1 < b.dims[0]; ++i) {
                ++st.cells;
                if (!gather(b, i, j, k, cell, node)) {
                    ++st.skipped_invalid;
                    continue;
                }
                int code = 0;
                for (int c = 0; c < 8; ++c)
                    if (cell.value[static_cast<std::size_t>(c)] >= iso) code |= 1 << c;
                const McCase& mc = table.cases[static_cast<std::size_t>(code)];
                if (mc.triangle_count == 0) continue;
                if (jacobian_sign(cell) == 0) {
                    ++st.skipped_degenerate;
                    continue;
                }
                const int n = hex_marching_cubes(cell, iso, left_handed, tris);
                ++st.active_cells;
                for (int t = 0; t < n; ++t) {
                    const std::uint8_t* e = &mc.edges[static_cast<std::size_t>(3 * t)];
                    // hex_marching_cubes' vertex order: e0, then e1/e2 swapped when left-handed
                    const int edge_of[3] = {e[0], e[left_handed ? 2 : 1], e[left_handed ? 1 : 2]};
                    for (int q = 0; q < 3; ++q) {
                        const int edge = edge_of[q];
                        const int a = kMcEdgeCorners[static_cast<std::size_t>(edge)][0];
                        const auto key = 3 * static_cast<std::uint64_t>(node[static_cast<std::size_t>(a)]) +
                                         static_cast<std::uint64_t>(edge / 4);
                        const auto [it, fresh] = vertex_of.try_emplace(key, static_cast<std::uint32_t>(edge_keys.size()));
                        if (fresh) {
                            if (edge_keys.size() >= std::numeric_limits<std::uint32_t>::max())
                                throw std::length_error("block marching cubes: more than 2^32-1 vertices in a piece");
                            const Vec3& p = tris[static_cast<std::size_t>(t)].v[static_cast<std::size_t>(q)];
                            m.xyz.insert(m.xyz.end(), {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
                            edge_keys.push_back(key);
                        }
                        m.tri.push_back(it->second);
                    }
                    m.block.push_back(block_id);
                }
            }
    return m;
}

}  // namespace meshless
