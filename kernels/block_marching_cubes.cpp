#include "kernels/block_marching_cubes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "kernels/block_cells.hpp"
#include "kernels/hex_marching_cubes.hpp"

namespace meshless {

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
                if (!gather_block_cell(b, i, j, k, cell, node)) {
                    ++st.skipped_invalid;
                    continue;
                }
                int code = 0;
                for (int c = 0; c < 8; ++c)
                    if (cell.value[static_cast<std::size_t>(c)] >= iso) code |= 1 << c;
                const McCase& mc = table.cases[static_cast<std::size_t>(code)];
                if (mc.triangle_count == 0) continue;
                if (hex_jacobian_sign(cell) == 0) {
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
