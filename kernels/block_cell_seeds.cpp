#include "kernels/block_cell_seeds.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

#include "kernels/barycentric_lattice.hpp"
#include "kernels/block_cells.hpp"
#include "kernels/errors.hpp"
#include "kernels/hex_marching_cubes.hpp"
#include "kernels/multiblock_splat_radius.hpp"

namespace meshless {

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Walks the cells [c0, c1) of a block in order, calling f(i, j, k).
template <class F>
void for_cells(const StructuredBlock& b, std::int64_t c0, std::int64_t c1, F&& f) {
    const std::int64_t cx = b.dims[0] - 1, cy = b.dims[1] - 1;
    if (c0 >= c1 || cx <= 0 || cy <= 0 || b.dims[2] < 2) return;
    std::int64_t i = c0 % cx, j = (c0 / cx) % cy, k = c0 / (cx * cy);
    for (std::int64_t c = c0; c < c1; ++c) {
        f(i, j, k);
        if (++i == cx) {
            i = 0;
            if (++j == cy) {
                j = 0;
                ++k;
            }
        }
    }
}

bool all_covered(const StructuredBlock& b, const std::array<std::int64_t, 8>& node) {
    if (b.covered.empty()) return false;
    for (std::int64_t n : node)
        if (!b.is_covered(n)) return false;
    return true;
}

bool crossed(const HexCell& cell, double iso) {
    bool above = false, below = false;
    for (double v : cell.value) {
        if (v >= iso) above = true;
        else below = true;
    }
    return above && below;
}

void grow(std::array<Vec3, 2>& box, bool& empty, const Vec3& p) {
    if (empty) {
        box = {p, p};
        empty = false;
        return;
    }
    box[0] = {std::min(box[0].x, p.x), std::min(box[0].y, p.y), std::min(box[0].z, p.z)};
    box[1] = {std::max(box[1].x, p.x), std::max(box[1].y, p.y), std::max(box[1].z, p.z)};
}

}  // namespace

BlockSeedPlan plan_block_seeds(const Multiblock& mb, double iso) {
    BlockSeedPlan plan;
    plan.first_cell.push_back(0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    plan.value_range = {nan, nan};
    bool no_nodes = true, no_active = true;
    for (const StructuredBlock& b : mb.blocks) {
        const bool dims_ok = b.dims[0] >= 1 && b.dims[1] >= 1 && b.dims[2] >= 1 &&
                             b.dims[0] <= std::numeric_limits<std::int64_t>::max() / b.dims[1] &&
                             b.dims[0] * b.dims[1] <= std::numeric_limits<std::int64_t>::max() / b.dims[2];
        if (!dims_ok || static_cast<std::int64_t>(b.node.size()) != b.node_count() || b.value.size() != b.node.size() ||
            (!b.valid.empty() && b.valid.size() != b.node.size()))
            throw InvalidArgument("block seed plan: block " + std::to_string(plan.orientation.size()) +
                                  " has node, value or valid arrays that do not match its dims");
        plan.orientation.push_back(block_orientation(b).left_handed() ? -1 : 1);
        plan.first_cell.push_back(plan.first_cell.back() + block_cell_count(b));
        for (std::int64_t n = 0; n < b.node_count(); ++n) {
            const auto u = static_cast<std::size_t>(n);
            if (!b.is_valid(n) || !std::isfinite(b.value[u]) || !finite(b.node[u])) continue;
            grow(plan.node_bounds, no_nodes, b.node[u]);
            const double v = b.value[u];
            if (!(v >= plan.value_range[0])) plan.value_range[0] = v;  // also replaces the initial NaN
            if (!(v <= plan.value_range[1])) plan.value_range[1] = v;
        }
        HexCell cell;
        std::array<std::int64_t, 8> node{};
        for_cells(b, 0, block_cell_count(b), [&](std::int64_t i, std::int64_t j, std::int64_t k) {
            if (!gather_block_cell(b, i, j, k, cell, node) || all_covered(b, node) || !crossed(cell, iso)) return;
            ++plan.active_cells;
            for (std::int64_t n : node) grow(plan.active_bounds, no_active, b.node[static_cast<std::size_t>(n)]);
        });
    }
    return plan;
}

void block_cell_seeds(const StructuredBlock& b, std::uint32_t block_id, int orientation, std::int64_t c0, std::int64_t c1,
                      double iso, int n, std::span<const std::array<double, 3>> lattice, std::vector<SeedRecord>& out,
                      BlockSeedStats& st) {
    assert(0 <= c0 && c0 <= c1 && c1 <= block_cell_count(b));
    assert(lattice.size() == lattice_size(n));
    const bool left_handed = orientation < 0;
    HexCell cell;
    std::array<HexTriangle, kMcMaxTriangles> tri;
    st.cells += c1 - c0;
    std::array<std::int64_t, 8> node{};
    for_cells(b, c0, c1, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
        if (!gather_block_cell(b, i, j, k, cell, node)) {
            ++st.invalid_cells;
            return;
        }
        if (all_covered(b, node)) {
            ++st.covered_cells;
            return;
        }
        if (!crossed(cell, iso)) return;
        const auto jac = hex_jacobian_range(cell.corner);
        if (left_handed ? !(jac[1] < 0) : !(jac[0] > 0)) {
            ++st.degenerate_cells;
            return;
        }
        const int nt = hex_marching_cubes(cell, iso, left_handed, tri);
        if (nt == 0) return;
        ++st.active_cells;
        // l of section 4.4: the longest of the four space diagonals (a curvilinear cell has four)
        double diag2 = 0;
        for (int q = 0; q < 4; ++q) {
            const Vec3 d = cell.corner[static_cast<std::size_t>(7 - q)] - cell.corner[static_cast<std::size_t>(q)];
            diag2 = std::max(diag2, dot(d, d));
        }
        const auto diagonal = static_cast<float>(std::sqrt(diag2));
        for (int t = 0; t < nt; ++t) {
            const auto& v = tri[static_cast<std::size_t>(t)].v;
            const Vec3 nrm = cross(v[1] - v[0], v[2] - v[0]);
            const double twice_area = norm(nrm);
            if (!(twice_area > 0)) {
                ++st.zero_area_triangles;
                continue;
            }
            ++st.triangles;
            const Vec3 unit = nrm * (1.0 / twice_area);
            const auto base = static_cast<float>(lattice_base_radius(0.5 * twice_area, n));
            for (const auto& w : lattice) {
                const Vec3 p = barycentric_point(w, v[0], v[1], v[2]);
                SeedRecord s;
                s.pos[0] = static_cast<float>(p.x);
                s.pos[1] = static_cast<float>(p.y);
                s.pos[2] = static_cast<float>(p.z);
                s.normal[0] = static_cast<float>(unit.x);
                s.normal[1] = static_cast<float>(unit.y);
                s.normal[2] = static_cast<float>(unit.z);
                s.value = static_cast<float>(iso);
                s.base_radius = base;
                s.cell_diagonal = diagonal;
                s.block = block_id;
                out.push_back(s);
            }
            st.seeds += static_cast<std::int64_t>(lattice.size());
        }
    });
}

}  // namespace meshless
