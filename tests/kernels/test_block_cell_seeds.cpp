// kernels/block_cell_seeds.hpp: marching-cubes seeds of structured blocks (dissertation section 4.4)
// against oracles: a sampled sphere (seeds near the sphere, value = iso, normals inward = towards
// decreasing values of |p|, VTK's convention, counts = triangles x n(n+1)/2), the same block mirrored
// (left-handed: detected, same seeds mirrored, normals still inward), blanked / NaN nodes (the 8 cells around an interior
// node skipped and counted), collapsed and inverted cells (skipped and counted), split cell ranges
// giving the same seeds as one range, and the plan's ranges and bounds.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "kernels/barycentric_lattice.hpp"
#include "kernels/block_cell_seeds.hpp"
#include "kernels/errors.hpp"

#include "multiblock_fixtures.hpp"

using namespace meshless;

namespace {

using Map = std::function<Vec3(double, double, double)>;
using Fn = std::function<double(const Vec3&)>;
using test::mapped_block;

Map cube_map(double lo, double h) {
    return [=](double i, double j, double k) { return Vec3{lo + h * i, lo + h * j, lo + h * k}; };
}

double sphere(const Vec3& p) { return norm(p); }

std::vector<SeedRecord> seeds_of(const StructuredBlock& b, double iso, int n, BlockSeedStats& st, std::uint32_t id = 0) {
    const auto lattice = barycentric_lattice(n);
    std::vector<SeedRecord> out;
    block_cell_seeds(b, id, block_orientation(b).left_handed() ? -1 : 1, 0, block_cell_count(b), iso, n, lattice, out, st);
    return out;
}

Vec3 pos(const SeedRecord& s) { return {s.pos[0], s.pos[1], s.pos[2]}; }
Vec3 nrm(const SeedRecord& s) { return {s.normal[0], s.normal[1], s.normal[2]}; }

}  // namespace

TEST_CASE("block seeds of a sampled sphere: near the sphere, normals to decreasing |p|, n(n+1)/2 per triangle", "[block-seeds]") {
    const double h = 2.0 / 16;
    const StructuredBlock b = mapped_block({17, 17, 17}, cube_map(-1, h), sphere);
    CHECK(block_cell_count(b) == 16 * 16 * 16);
    CHECK_FALSE(block_orientation(b).left_handed());
    for (int n : {1, 3}) {
        BlockSeedStats st;
        const auto s = seeds_of(b, 0.6, n, st, 7);
        CHECK(st.cells == 4096);
        CHECK(st.invalid_cells == 0);
        CHECK(st.degenerate_cells == 0);
        CHECK(st.active_cells > 100);
        CHECK(st.seeds == st.triangles * static_cast<std::int64_t>(lattice_size(n)));
        REQUIRE(static_cast<std::int64_t>(s.size()) == st.seeds);
        for (const auto& r : s) {
            CHECK(std::abs(norm(pos(r)) - 0.6) < 0.25 * h);  // the trilinear MC surface's distance is O(h^2)
            CHECK(dot(nrm(r), normalized(pos(r))) < -0.8);   // towards decreasing |p| (VTK's convention)
            CHECK_THAT(norm(nrm(r)), Catch::WithinAbs(1.0, 1e-6));
            CHECK(r.value == 0.6f);
            CHECK(r.base_radius > 0);
            CHECK_THAT(r.cell_diagonal, Catch::WithinRel(h * std::sqrt(3.0), 1e-6));
            CHECK(r.block == 7u);
        }
    }
}

TEST_CASE("block seeds: a mirrored (left-handed) block is detected and still gives normals to decreasing values", "[block-seeds]") {
    const double h = 2.0 / 12;
    const StructuredBlock right = mapped_block({13, 13, 13}, cube_map(-1, h), sphere);
    const StructuredBlock left = mapped_block({13, 13, 13}, [&](double i, double j, double k) {
        return Vec3{1 - h * i, -1 + h * j, -1 + h * k};  // x reversed
    }, sphere);
    CHECK(block_orientation(left).left_handed());
    BlockSeedStats sr, sl;
    const auto r = seeds_of(right, 0.55, 2, sr);
    const auto l = seeds_of(left, 0.55, 2, sl);
    CHECK(sl.degenerate_cells == 0);
    CHECK(sl.seeds == sr.seeds);
    for (const auto& s : l) CHECK(dot(nrm(s), normalized(pos(s))) < -0.8);
    // without the orientation the normals would point outwards (towards increasing |p|)
    std::vector<SeedRecord> wrong;
    BlockSeedStats sw;
    block_cell_seeds(left, 0, +1, 0, block_cell_count(left), 0.55, 2, barycentric_lattice(2), wrong, sw);
    CHECK(sw.seeds == 0);
    CHECK(sw.degenerate_cells == sl.active_cells);  // every crossed cell is inverted for a right-handed reading
}

TEST_CASE("block seeds: cells with a blanked or NaN corner are skipped and counted", "[block-seeds]") {
    const double h = 0.25;
    StructuredBlock b = mapped_block({9, 9, 9}, cube_map(-1, h), sphere);
    BlockSeedStats clean;
    seeds_of(b, 0.6, 2, clean);
    b.valid.assign(b.node.size(), 1);
    b.valid[static_cast<std::size_t>(b.index(4, 4, 4))] = 0;  // interior: 8 cells
    b.value[static_cast<std::size_t>(b.index(0, 0, 0))] = std::numeric_limits<double>::quiet_NaN();  // corner: 1 cell
    b.node[static_cast<std::size_t>(b.index(8, 8, 4))].x = std::numeric_limits<double>::infinity();  // edge: 2 cells
    BlockSeedStats st;
    const auto s = seeds_of(b, 0.6, 2, st);
    CHECK(st.cells == 512);
    CHECK(st.invalid_cells == 8 + 1 + 2);
    for (const auto& r : s) CHECK(std::isfinite(r.pos[0]));
    CHECK(st.seeds <= clean.seeds);
    // the plan ignores them too
    Multiblock mb;
    mb.blocks.push_back(b);
    const BlockSeedPlan plan = plan_block_seeds(mb, 0.6);
    CHECK(std::isfinite(plan.value_range[0]));
    CHECK(std::isfinite(plan.node_bounds[1].x));
}

TEST_CASE("block seeds: collapsed and inverted cells are skipped and counted", "[block-seeds]") {
    // f = x; iso between node columns i = 5 and 6: every cell with i = 5 is crossed
    const Fn fx = [](const Vec3& p) { return p.x; };
    for (double shift : {1.0, 1.5}) {  // 1.0: node (5,5,5) onto (6,5,5) (collapsed), 1.5: past it (inverted)
        StructuredBlock b = mapped_block({11, 11, 11}, cube_map(0, 1), fx);
        const auto at = static_cast<std::size_t>(b.index(5, 5, 5));
        b.node[at].x += shift;  // the value stays: only the geometry breaks
        BlockSeedStats st;
        const auto s = seeds_of(b, 5.5, 2, st);
        CHECK(st.degenerate_cells >= 4);  // the 4 cells around the edge (5..6, 5, 5)
        CHECK(st.active_cells + st.degenerate_cells == 10 * 10);
        CHECK(st.seeds == st.triangles * 3);
        CHECK_FALSE(block_orientation(b).left_handed());
    }
}

TEST_CASE("block seeds: split cell ranges give the seeds of one range, blocks without cells give none", "[block-seeds]") {
    const StructuredBlock b = mapped_block({10, 7, 6}, [](double i, double j, double k) {
        return Vec3{i * 0.3 + 0.05 * j, j * 0.25, k * 0.4 + 0.02 * i * i};  // curvilinear
    }, [](const Vec3& p) { return std::sin(2 * p.x) + std::cos(3 * p.y) * p.z; });
    const auto lattice = barycentric_lattice(3);
    const int o = block_orientation(b).left_handed() ? -1 : 1;
    std::vector<SeedRecord> whole, parts;
    BlockSeedStats s1, s2;
    block_cell_seeds(b, 1, o, 0, block_cell_count(b), 0.3, 3, lattice, whole, s1);
    for (std::int64_t c = 0; c < block_cell_count(b); c += 37)
        block_cell_seeds(b, 1, o, c, std::min(block_cell_count(b), c + 37), 0.3, 3, lattice, parts, s2);
    REQUIRE(whole.size() == parts.size());
    REQUIRE(!whole.empty());
    CHECK(std::memcmp(whole.data(), parts.data(), whole.size() * sizeof(SeedRecord)) == 0);
    CHECK(s1.cells == s2.cells);
    CHECK(s1.triangles == s2.triangles);

    const StructuredBlock flat = mapped_block({5, 5, 1}, cube_map(0, 1), [](const Vec3& p) { return p.x; });
    CHECK(block_cell_count(flat) == 0);
}

TEST_CASE("block seed plan: value range, crossed cells, bounds, global cell numbering", "[block-seeds]") {
    Multiblock mb;
    mb.blocks.push_back(mapped_block({5, 5, 5}, cube_map(0, 1), [](const Vec3& p) { return p.x; }));
    mb.blocks.push_back(mapped_block({3, 3, 1}, cube_map(0, 1), [](const Vec3& p) { return p.x; }));  // no cells
    mb.blocks.push_back(mapped_block({3, 4, 5}, cube_map(10, 0.5), [](const Vec3& p) { return p.x - 9; }));
    const BlockSeedPlan plan = plan_block_seeds(mb, 1.5);
    REQUIRE(plan.first_cell.size() == 4);
    CHECK(plan.first_cell[1] == 64);
    CHECK(plan.first_cell[2] == 64);
    CHECK(plan.total_cells() == 64 + 2 * 3 * 4);
    CHECK(plan.value_range[0] == 0.0);
    CHECK(plan.value_range[1] == 4.0);
    // block 0: the 16 cells with x in [1,2]; block 2 (values 1, 1.5, 2 along i; a corner is above
    // when >= iso): only its 3 x 4 cells with i = 0
    CHECK(plan.active_cells == 16 + 3 * 4);
    CHECK(plan.active_bounds[0].x == 1.0);
    CHECK(plan.active_bounds[1].x == 10.5);
    CHECK(plan.node_bounds[1].z == 12.0);
    CHECK(plan.orientation == std::vector<int>{1, 1, 1});
    const BlockSeedPlan none = plan_block_seeds(mb, 100);
    CHECK(none.active_cells == 0);
}

TEST_CASE("block seed plan: blocks whose arrays do not match their dims are refused", "[block-seeds]") {
    Multiblock mb;
    mb.blocks.push_back(mapped_block({3, 3, 3}, cube_map(0, 1), sphere));
    mb.blocks[0].value.pop_back();
    CHECK_THROWS_AS(plan_block_seeds(mb, 1.0), InvalidArgument);
    mb.blocks[0] = mapped_block({3, 3, 3}, cube_map(0, 1), sphere);
    mb.blocks[0].valid.assign(5, 1);
    CHECK_THROWS_AS(plan_block_seeds(mb, 1.0), InvalidArgument);
    mb.blocks[0].valid.clear();
    mb.blocks[0].dims = {3, 3, 4};
    CHECK_THROWS_AS(plan_block_seeds(mb, 1.0), InvalidArgument);
    mb.blocks[0].dims = {3, 3, 3};
    CHECK_NOTHROW(plan_block_seeds(mb, 1.0));
}
