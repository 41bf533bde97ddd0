// Tests for kernels/crack_edges.hpp, kernels/triangle_pair_intersections.hpp and
// kernels/hex_point_location.hpp on the naive per-block marching cubes of analytic blocks: one
// block and conforming blocks are crack- and intersection-free, overlapping blocks intersect,
// semi-conforming blocks (one at half resolution) crack, overlapping blocks with coincident nodes
// duplicate their surface; the CGAL count equals an O(n^2) count; hand-made pairs of each kind.
#include <catch2/catch.hpp>

#include <memory>

#include "kernels/block_marching_cubes.hpp"
#include "kernels/crack_edges.hpp"
#include "kernels/hex_point_location.hpp"
#include "kernels/triangle_pair_intersections.hpp"
#include "multiblock_fixtures.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

struct Naive {
    Mesh mesh;
    WeldedMesh welded;
    CrackEdgeStats cracks;
    TrianglePairStats pairs;
};

/// Every block contoured whole (block id = index), concatenated, then the --stats measures.
Naive naive(const std::vector<StructuredBlock>& blocks, double iso) {
    Naive n;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        BlockMcStats st;
        std::vector<std::uint64_t> keys;
        const Mesh m = block_marching_cubes(blocks[b], iso, block_orientation(blocks[b]).left_handed(), 0, blocks[b].dims[2],
                                            static_cast<std::uint32_t>(b), st, keys);
        const auto base = static_cast<std::uint32_t>(n.mesh.vertex_count());
        n.mesh.xyz.insert(n.mesh.xyz.end(), m.xyz.begin(), m.xyz.end());
        for (std::uint32_t t : m.tri) n.mesh.tri.push_back(base + t);
        n.mesh.block.insert(n.mesh.block.end(), m.block.begin(), m.block.end());
    }
    n.welded = weld_by_position(n.mesh);
    std::vector<std::unique_ptr<BlockCellLocator>> loc;
    for (const auto& b : blocks) loc.push_back(std::make_unique<BlockCellLocator>(b));
    n.cracks = count_crack_edges(n.welded, [&](const Vec3& p, std::uint32_t own) {
        for (std::size_t b = 0; b < loc.size(); ++b)
            if (b != own && loc[b]->contains(p)) return true;
        return false;
    });
    n.pairs = count_intersecting_triangle_pairs(n.welded.xyz, n.welded.tri, n.welded.block);
    return n;
}

/// Nodes x in [x0, x1], y and z in [-1, 1], spacing h (all multiples of h: shared nodes are bitwise equal).
StructuredBlock box(const std::string& name, double x0, double x1, double h) {
    const auto i0 = static_cast<std::int64_t>(std::llround(x0 / h)), i1 = static_cast<std::int64_t>(std::llround(x1 / h));
    const auto n = static_cast<std::int64_t>(std::llround(1 / h));
    return index_block(name, {i0, -n, -n}, {i1 - i0 + 1, 2 * n + 1, 2 * n + 1}, h, sphere_field);
}

}  // namespace

TEST_CASE("naive stats: one block holding a closed sphere has no boundary, cracks or intersections", "[block_mc][cracks]") {
    const Naive n = naive({sphere_block()}, 0.6);
    CHECK(n.cracks.boundary_edges == 0);
    CHECK(n.cracks.crack_edges == 0);
    CHECK(n.cracks.nonmanifold_edges == 0);
    // (triangles whose corners coincide after welding -- a crossing at a node -- have no edges)
    CHECK(n.cracks.edges * 2 == static_cast<std::int64_t>(3 * (n.mesh.triangle_count() - n.cracks.degenerate_triangles)));
    CHECK(n.pairs.intersecting == 0);
    CHECK(n.pairs.candidates == 0);  // one block: no pair of different blocks
}

TEST_CASE("naive stats: a sphere cut at a plane the blocks share (same nodes) is seamless", "[block_mc][cracks]") {
    const Naive n = naive({box("left", -1, 0, 0.1), box("right", 0, 1, 0.1)}, 0.6);
    CHECK(n.welded.xyz.size() < n.mesh.xyz.size());  // vertices on x = 0 welded across the blocks
    CHECK(n.cracks.boundary_edges == 0);
    CHECK(n.cracks.crack_edges == 0);
    CHECK(n.pairs.intersecting == 0);
    CHECK(n.pairs.duplicates == 0);
    CHECK(n.pairs.candidates > 0);
}

TEST_CASE("naive stats: semi-conforming blocks (one at half resolution) crack at their interface", "[block_mc][cracks]") {
    const Naive n = naive({box("fine", -1, 0, 0.1), box("coarse", 0, 1, 0.2)}, 0.6);
    CHECK(n.cracks.boundary_edges > 0);
    CHECK(n.cracks.crack_edges > 0);
    CHECK(n.cracks.crack_edges == n.cracks.boundary_edges);  // the sphere crosses no outer face
    CHECK(n.cracks.nonmanifold_edges == 0);
}

TEST_CASE("naive stats: overlapping blocks intersect and crack", "[block_mc][cracks]") {
    // staggered lattices over x in [-0.25, 0.3]: two different linear approximations of the sphere
    const Naive n = naive({box("a", -1, 0.3, 0.1), lattice_block("b", {14, 21, 21}, {-0.25, -1, -1}, {0.1, 0.1, 0.1}, sphere_field)},
                          0.6);
    CHECK(n.pairs.intersecting > 0);
    CHECK(n.pairs.duplicates == 0);
    CHECK(n.cracks.crack_edges > 0);
    CHECK(n.cracks.crack_edges == n.cracks.boundary_edges);
}

TEST_CASE("naive stats: overlapping blocks with coincident nodes duplicate their surface", "[block_mc][cracks]") {
    const Naive n = naive({box("a", -1, 0.3, 0.1), box("b", -0.3, 1, 0.1)}, 0.6);
    CHECK(n.pairs.duplicates > 0);
    CHECK(n.pairs.intersecting == 0);
    CHECK(n.cracks.nonmanifold_edges > 0);  // where one copy ends inside the other
    CHECK(n.cracks.crack_edges == 0);
}

TEST_CASE("naive stats: the CGAL box-filtered count equals the O(n^2) count", "[block_mc][cracks]") {
    const Naive n = naive({box("a", -1, 0.4, 0.2), lattice_block("b", {8, 11, 11}, {-0.3, -1, -1}, {0.2, 0.2, 0.2}, sphere_field)},
                          0.6);
    const TrianglePairStats brute = count_intersecting_triangle_pairs_brute_force(n.welded.xyz, n.welded.tri, n.welded.block);
    CHECK(n.pairs.intersecting > 0);
    CHECK(brute.intersecting == n.pairs.intersecting);
    CHECK(brute.duplicates == n.pairs.duplicates);
    CHECK(brute.degenerate == n.pairs.degenerate);
    CHECK(brute.candidates > n.pairs.candidates);
}

TEST_CASE("triangle pairs: hand-made pairs of each kind", "[cracks]") {
    // vertices: a square in z = 0 and points above/below
    const std::vector<double> xyz = {0, 0, 0,  1, 0, 0,  0, 1, 0,  1, 1, 0,   // 0..3
                                     0.2, 0.2, -1,  0.2, 0.2, 1,              // 4, 5: a vertical stick through (0.2, 0.2)
                                     0.3, 0.3, 0,  -1, 0, 0,  -1, 1, 0,       // 6: inside triangle 0-1-2; 7, 8
                                     2, 2, 0,  3, 3, 0};                      // 9, 10: collinear with 0
    auto count = [&](std::vector<std::uint32_t> tri) {
        const std::vector<std::uint32_t> group = {0, 1};
        const auto box = count_intersecting_triangle_pairs(xyz, tri, group);
        const auto brute = count_intersecting_triangle_pairs_brute_force(xyz, tri, group);
        REQUIRE(box.intersecting == brute.intersecting);
        REQUIRE(box.duplicates == brute.duplicates);
        return box;
    };
    CHECK(count({0, 1, 2, 4, 5, 3}).intersecting == 1);             // crossing, nothing shared
    CHECK(count({0, 1, 2, 1, 3, 2}).intersecting == 0);             // shared edge, coplanar, opposite sides
    CHECK(count({0, 1, 2, 1, 2, 6}).intersecting == 1);             // shared edge, coplanar, same side: overlap
    CHECK(count({0, 1, 2, 1, 2, 5}).intersecting == 0);             // shared edge, not coplanar
    CHECK(count({0, 1, 2, 0, 7, 8}).intersecting == 0);             // shared vertex only
    CHECK(count({0, 1, 2, 0, 6, 5}).intersecting == 1);             // shared vertex, the other enters it
    CHECK(count({0, 1, 2, 2, 1, 0}).duplicates == 1);               // same vertices
    CHECK(count({0, 1, 2, 0, 9, 10}).degenerate == 1);              // collinear: skipped
    const std::vector<std::uint32_t> same_group = {0, 0};
    CHECK(count_intersecting_triangle_pairs(xyz, std::vector<std::uint32_t>{0, 1, 2, 4, 5, 3}, same_group).intersecting == 0);
    CHECK_THROWS_AS(count_intersecting_triangle_pairs(xyz, std::vector<std::uint32_t>{0, 1, 99}, std::vector<std::uint32_t>{0}),
                    std::invalid_argument);
}

TEST_CASE("hex point location: inside, outside and on the faces of curvilinear cells", "[cracks]") {
    // a sheared, twisted block: x' = x + 0.3 y, z' = z + 0.2 x y
    StructuredBlock b = lattice_block("sheared", {4, 4, 4}, {0, 0, 0}, {1, 1, 1}, sphere_field);
    for (auto& p : b.node) p = {p.x + 0.3 * p.y, p.y, p.z + 0.2 * p.x * p.y};
    const BlockCellLocator loc(b);
    auto map = [](double x, double y, double z) { return Vec3{x + 0.3 * y, y, z + 0.2 * (x + 0.3 * y) * y}; };
    CHECK(loc.valid_cells() == 27);
    CHECK(loc.contains(map(1.5, 1.5, 1.5)));
    CHECK(loc.contains(map(0.01, 2.9, 0.2)));
    CHECK(loc.contains(map(0, 1.5, 1.5)));        // on the boundary face
    CHECK_FALSE(loc.contains(map(-0.1, 1.5, 1.5)));
    CHECK_FALSE(loc.contains(map(1.5, 3.2, 1.5)));
    CHECK_FALSE(loc.contains({100, 0, 0}));
    // a blanked node removes its cells
    b.valid.assign(static_cast<std::size_t>(b.node_count()), 1);
    b.valid[static_cast<std::size_t>(b.index(0, 0, 0))] = 0;
    const BlockCellLocator blanked(b);
    CHECK(blanked.valid_cells() == 26);
    CHECK_FALSE(blanked.contains(map(0.5, 0.5, 0.5)));
}

TEST_CASE("weld by position: -0 and +0 weld, block ids are kept", "[cracks]") {
    Mesh m;
    m.xyz = {0.0f, 0, 0, 1, 0, 0, 0, 1, 0, -0.0f, 0, 0, 1, 0, 0, 0, 0, 1};
    m.tri = {0, 1, 2, 3, 4, 5};
    m.block = {3, 4};
    const WeldedMesh w = weld_by_position(m);
    CHECK(w.xyz.size() == 3 * 4);
    CHECK(w.tri == std::vector<std::uint32_t>{0, 1, 2, 0, 1, 3});
    CHECK(w.block == m.block);
    const CrackEdgeStats s = count_crack_edges(w, [](const Vec3&, std::uint32_t) { return true; });
    CHECK(s.edges == 5);
    CHECK(s.boundary_edges == 4);
    CHECK(s.crack_edges == 4);
}
