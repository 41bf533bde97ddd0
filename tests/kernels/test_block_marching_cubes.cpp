// Tests for kernels/block_marching_cubes.hpp: a closed sphere from one block (every edge shared by
// exactly two triangles) facing decreasing values (VTK's convention: inwards for the distance |p|,
// outwards for a ball with high values inside), left-handed blocks oriented alike, block ids,
// skipped cells (invalid corner, collapsed cell) counted, and pieces of cell layers that weld to the
// one-piece mesh.
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <utility>

#include "kernels/block_marching_cubes.hpp"
#include "multiblock_fixtures.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

Mesh whole(const StructuredBlock& b, double iso, std::uint32_t id, BlockMcStats& st) {
    std::vector<std::uint64_t> keys;
    return block_marching_cubes(b, iso, block_orientation(b).left_handed(), 0, b.dims[2], id, st, keys);
}

/// Edge -> number of triangles using it.
std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_use(const Mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> use;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int q = 0; q < 3; ++q) {
            const std::uint32_t a = m.tri[3 * t + q], b = m.tri[3 * t + (q + 1) % 3];
            ++use[{std::min(a, b), std::max(a, b)}];
        }
    return use;
}

/// 6 x the signed volume enclosed (positive when the triangles face outwards).
double signed_volume6(const Mesh& m) {
    double v = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        Vec3 p[3];
        for (int q = 0; q < 3; ++q) {
            const float* x = &m.xyz[3 * m.tri[3 * t + q]];
            p[q] = {x[0], x[1], x[2]};
        }
        v += dot(p[0], cross(p[1], p[2]));
    }
    return v;
}

}  // namespace

TEST_CASE("block marching cubes: a sphere inside one block is closed and faces decreasing values", "[block_mc]") {
    const StructuredBlock b = sphere_block();
    BlockMcStats st;
    const Mesh m = whole(b, 0.6, 7, st);
    REQUIRE(m.triangle_count() > 100);
    for (const auto& [e, n] : edge_use(m)) {
        INFO("edge " << e.first << "-" << e.second);
        REQUIRE(n == 2);
    }
    // |p| grows outwards: the triangles face the centre (VTK's convention), negative signed volume
    const double volume = signed_volume6(m) / 6;
    CHECK(volume == Approx(-4.0 / 3.0 * M_PI * 0.216).epsilon(0.05));
    CHECK(std::all_of(m.block.begin(), m.block.end(), [](std::uint32_t id) { return id == 7; }));
    CHECK(m.block.size() == m.triangle_count());
    CHECK(st.cells == 20 * 20 * 20);
    CHECK(st.skipped_invalid == 0);
    CHECK(st.skipped_degenerate == 0);
    // every vertex on the sphere within the chord error
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const double r = std::sqrt(double(m.xyz[3 * v]) * m.xyz[3 * v] + double(m.xyz[3 * v + 1]) * m.xyz[3 * v + 1] +
                                   double(m.xyz[3 * v + 2]) * m.xyz[3 * v + 2]);
        REQUIRE(std::fabs(r - 0.6) < 0.02);
    }
}

TEST_CASE("block marching cubes: a left-handed block gives the same outward surface around high values", "[block_mc]") {
    // a ball: high values inside (2 - |p|), iso 1.4 at |p| = 0.6; VTK's convention faces it outwards
    const auto ball = [](const Vec3& p) { return 2.0 - sphere_field(p); };
    const StructuredBlock right = lattice_block("ball", {11, 11, 11}, {-1, -1, -1}, {0.2, 0.2, 0.2}, ball);
    const StructuredBlock left = lattice_block("flipped", {11, 11, 11}, {-1, -1, -1}, {0.2, 0.2, 0.2}, ball, true);
    CHECK_FALSE(block_orientation(right).left_handed());
    const BlockOrientation o = block_orientation(left);
    CHECK(o.left_handed());
    CHECK(o.negative == 1000);
    BlockMcStats s1, s2;
    const Mesh a = whole(right, 1.4, 0, s1), b = whole(left, 1.4, 0, s2);
    CHECK(a.triangle_count() == b.triangle_count());
    CHECK(signed_volume6(a) / 6 == Approx(4.0 / 3.0 * M_PI * 0.216).epsilon(0.1));
    CHECK(signed_volume6(b) == Approx(signed_volume6(a)).epsilon(1e-3));  // crossings from the other end: rounding
    // forced the wrong way, the same block faces inwards
    std::vector<std::uint64_t> keys;
    BlockMcStats s3;
    CHECK(signed_volume6(block_marching_cubes(left, 1.4, false, 0, 10, 0, s3, keys)) < 0);
}

TEST_CASE("block marching cubes: cells with an invalid corner or collapsed are skipped and counted", "[block_mc]") {
    StructuredBlock b = sphere_block(11);
    b.valid.assign(static_cast<std::size_t>(b.node_count()), 1);
    b.valid[static_cast<std::size_t>(b.index(5, 5, 2))] = 0;  // interior node: its 8 cells go
    b.value[static_cast<std::size_t>(b.index(0, 0, 0))] = std::nan("");  // corner node: 1 cell
    // collapse cell (8, 8, 8) far from the sphere: node (9, 9, 9) onto node (8, 8, 8); and cell (7, 5, 5),
    // which the sphere crosses (|p| from 0.4 to 0.66): node (8, 6, 6) onto node (7, 5, 5)
    b.node[static_cast<std::size_t>(b.index(9, 9, 9))] = b.node[static_cast<std::size_t>(b.index(8, 8, 8))];
    b.node[static_cast<std::size_t>(b.index(8, 6, 6))] = b.node[static_cast<std::size_t>(b.index(7, 5, 5))];
    BlockMcStats st;
    const Mesh m = whole(b, 0.6, 0, st);
    CHECK(st.skipped_invalid == 9);
    CHECK(st.skipped_degenerate >= 1);
    CHECK(st.cells == 1000);
    const BlockOrientation o = block_orientation(b);
    CHECK(o.invalid == 9);
    CHECK(o.degenerate > st.skipped_degenerate);  // the census counts the uncrossed collapsed cells too
    CHECK(o.positive + o.negative + o.degenerate + o.invalid == 1000);
    // the hole at the blanked node leaves boundary edges
    int boundary = 0;
    for (const auto& [e, n] : edge_use(m)) boundary += n == 1;
    CHECK(boundary > 0);
}

TEST_CASE("block marching cubes: pieces of cell layers share their layer's vertices by key", "[block_mc]") {
    const StructuredBlock b = sphere_block(13);
    BlockMcStats st;
    std::vector<std::uint64_t> all_keys, k1, k2;
    const Mesh all = block_marching_cubes(b, 0.6, false, 0, 12, 0, st, all_keys);
    const Mesh lo = block_marching_cubes(b, 0.6, false, 0, 6, 0, st, k1);
    const Mesh hi = block_marching_cubes(b, 0.6, false, 6, 12, 0, st, k2);
    CHECK(lo.triangle_count() + hi.triangle_count() == all.triangle_count());
    // vertices with the same key have bitwise equal positions, and the keys of the shared layer are in both
    std::map<std::uint64_t, std::array<float, 3>> pos;
    auto add = [&](const Mesh& m, const std::vector<std::uint64_t>& keys) {
        for (std::size_t v = 0; v < keys.size(); ++v) {
            const std::array<float, 3> p{m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]};
            const auto [it, fresh] = pos.emplace(keys[v], p);
            if (!fresh) REQUIRE(it->second == p);
        }
    };
    add(all, all_keys);
    add(lo, k1);
    add(hi, k2);
    CHECK(pos.size() == all.vertex_count());
    CHECK(k1.size() + k2.size() > all.vertex_count());
}

TEST_CASE("block marching cubes: flat blocks and empty layer ranges give nothing", "[block_mc]") {
    const StructuredBlock flat = lattice_block("flat", {5, 5, 1}, {0, 0, 0}, {1, 1, 1}, sphere_field);
    BlockMcStats st;
    std::vector<std::uint64_t> keys;
    CHECK(block_marching_cubes(flat, 1.5, false, 0, 10, 0, st, keys).triangle_count() == 0);
    CHECK(block_orientation(flat).positive == 0);
    const StructuredBlock b = sphere_block(5);
    CHECK(block_marching_cubes(b, 0.6, false, 3, 3, 0, st, keys).triangle_count() == 0);
    CHECK(st.cells == 0);
}
