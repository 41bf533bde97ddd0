// The binning grid of scattered data (dissertation section 5.3): the depth-first rule's levels and
// their lower median on hand-made octrees, duplicates and the depth cap (never an unbounded
// recursion), the one-layer border around the points' bounding box (with a 1e6 offset and
// anisotropic extents), degenerate (planar, linear) inputs, the --max-cells coarsening, and the
// counting-sort binning against a brute-force count.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "kernels/errors.hpp"
#include "kernels/scattered_binning_grid.hpp"

using namespace meshless;

namespace {

/// The centres of the 4^3 level-2 cells of the unit cube, x fastest.
std::vector<Vec3> level2_centres() {
    std::vector<Vec3> p;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) p.push_back({(i + 0.5) / 4, (j + 0.5) / 4, (k + 0.5) / 4});
    return p;
}

constexpr std::array<bool, 3> kAll{true, true, true};

}  // namespace

TEST_CASE("binning rule: the lower median of a list of levels", "[kernels][scattered]") {
    CHECK(median_level({}) == 0);
    CHECK(median_level({3}) == 3);
    CHECK(median_level({1, 2}) == 1);
    CHECK(median_level({3, 1, 2}) == 2);
    CHECK(median_level({5, 1, 1, 5, 2, 7}) == 2);
}

TEST_CASE("binning rule on hand-made octrees: leaves and nodes with an empty child give their level", "[kernels][scattered]") {
    SECTION("one point per octant: eight leaves at level 1") {
        std::vector<Vec3> p;
        for (int c = 0; c < 8; ++c) p.push_back({(c & 1) ? 0.75 : 0.25, (c & 2) ? 0.75 : 0.25, (c & 4) ? 0.75 : 0.25});
        const auto l = binning_rule_levels(p, kAll, 30);
        CHECK(l == std::vector<int>(8, 1));
        CHECK(median_level(l) == 1);
    }
    SECTION("an empty octant stops the walk at the root") {
        std::vector<Vec3> p = level2_centres();
        std::erase_if(p, [](const Vec3& v) { return v.x > 0.5 && v.y > 0.5 && v.z > 0.5; });
        CHECK(binning_rule_levels(p, kAll, 30) == std::vector<int>{0});
    }
    SECTION("a full 4^3 lattice gives 64 leaves at level 2") {
        const auto l = binning_rule_levels(level2_centres(), kAll, 30);
        CHECK(l == std::vector<int>(64, 2));
        CHECK(median_level(l) == 2);
    }
    SECTION("octants with an empty child give level 1, the full ones their leaves at level 2") {
        std::vector<Vec3> p = level2_centres();
        // remove the lowest cell of octants 0..5 (their corner at the cube's corner of that octant)
        std::vector<Vec3> q;
        for (const Vec3& v : p) {
            const int oct = (v.x > 0.5) + 2 * (v.y > 0.5) + 4 * (v.z > 0.5);
            const bool corner = std::abs(v.x - ((oct & 1) ? 0.625 : 0.125)) < 1e-12 && std::abs(v.y - ((oct & 2) ? 0.625 : 0.125)) < 1e-12 &&
                                std::abs(v.z - ((oct & 4) ? 0.625 : 0.125)) < 1e-12;
            if (oct < 6 && corner) continue;
            q.push_back(v);
        }
        REQUIRE(q.size() == 58);
        const auto l = binning_rule_levels(q, kAll, 30);
        // depth-first, octants in order: six 1s, then 8 + 8 leaves at level 2
        std::vector<int> expect(6, 1);
        expect.insert(expect.end(), 16, 2);
        CHECK(l == expect);
        CHECK(median_level(l) == 2);  // 22 entries: the 11th smallest is a 2
        // with seven octants pruned: seven 1s and eight 2s, median 2; with all eight: 1
    }
    SECTION("the depth cap turns a node into a list entry") {
        const auto l = binning_rule_levels(level2_centres(), kAll, 1);
        CHECK(l == std::vector<int>(8, 1));
    }
    SECTION("duplicates and near-duplicates end the walk (two points never fill eight children)") {
        std::vector<Vec3> p = level2_centres();
        for (int i = 0; i < 1000; ++i) p.push_back({0.125, 0.125, 0.125});
        for (int i = 0; i < 100; ++i) p.push_back({0.125 + 1e-15 * i, 0.125, 0.125});
        const auto l = binning_rule_levels(p, kAll, 30);
        CHECK(l.size() == 64);
        CHECK(*std::max_element(l.begin(), l.end()) <= 3);
    }
    SECTION("an unsplit axis (planar data): four children per node") {
        std::vector<Vec3> p;
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) p.push_back({(i + 0.5) / 4, (j + 0.5) / 4, 0});
        CHECK(binning_rule_levels(p, {true, true, false}, 30) == std::vector<int>(16, 2));
    }
}

TEST_CASE("binning grid: one layer of cells surrounds the bounding box (offset 1e6, anisotropic)", "[kernels][scattered]") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> p;
    for (int i = 0; i < 5000; ++i) p.push_back({1e6 + 300 * u(rng), -2e6 + 40 * u(rng), 5 + 2 * u(rng)});
    const BinningGrid g = make_binning_grid(p);
    CHECK(g.level == 3);  // 5000 uniform points: level-3 cells hold ~10 points, level-4 cells ~1.2 (some empty)
    CHECK_FALSE(g.coarsened);
    for (int a = 0; a < 3; ++a) {
        const auto ua = static_cast<std::size_t>(a);
        CHECK(g.dims[ua] == (1 << g.level) + 2);
        // cells 1 .. dims-2 span exactly the bounding box
        CHECK(g.origin[a] + g.cell[a] == Approx(g.bounds[0][a]).epsilon(1e-12));
        CHECK(g.origin[a] + double(g.dims[ua] - 1) * g.cell[a] == Approx(g.bounds[1][a]).epsilon(1e-12));
    }
    const BinnedPoints b = bin_points(g, p);
    std::vector<std::uint32_t> count(static_cast<std::size_t>(g.cell_count()), 0);
    for (const Vec3& v : p) {
        const auto c = g.cell_of(v);
        for (int a = 0; a < 3; ++a) {
            CHECK(c[static_cast<std::size_t>(a)] >= 1);
            CHECK(c[static_cast<std::size_t>(a)] <= g.dims[static_cast<std::size_t>(a)] - 2);
        }
        ++count[static_cast<std::size_t>(g.index(c[0], c[1], c[2]))];
    }
    std::int64_t empty = 0, border = 0;
    for (std::int64_t k = 0; k < g.dims[2]; ++k)
        for (std::int64_t j = 0; j < g.dims[1]; ++j)
            for (std::int64_t i = 0; i < g.dims[0]; ++i) {
                const auto c = g.index(i, j, k);
                REQUIRE(b.points_of(c).size() == count[static_cast<std::size_t>(c)]);
                const bool on_border = i == 0 || j == 0 || k == 0 || i == g.dims[0] - 1 || j == g.dims[1] - 1 || k == g.dims[2] - 1;
                if (on_border) {
                    CHECK(count[static_cast<std::size_t>(c)] == 0);
                    ++border;
                }
                empty += count[static_cast<std::size_t>(c)] == 0;
                // stable: input order within a cell
                const auto pts = b.points_of(c);
                for (std::size_t q = 1; q < pts.size(); ++q) CHECK(pts[q - 1] < pts[q]);
            }
    CHECK(b.empty_cells == empty);
    CHECK(b.empty_interior_cells == empty - border);
}

TEST_CASE("binning grid: planar and linear data get one interior cell along the missing axes", "[kernels][scattered]") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> plane, line;
    for (int i = 0; i < 2000; ++i) {
        plane.push_back({u(rng), u(rng), 7.0});
        line.push_back({0, 0, 10 * u(rng)});
    }
    const BinningGrid gp = make_binning_grid(plane);
    CHECK(gp.degenerate == std::array<bool, 3>{false, false, true});
    CHECK(gp.dims[2] == 3);
    CHECK(gp.level >= 3);
    CHECK(gp.cell_of({0.5, 0.5, 7.0})[2] == 1);
    CHECK(gp.cell_centre(1, 1, 1).z == Approx(7.0));
    const BinningGrid gl = make_binning_grid(line);
    CHECK(gl.degenerate == std::array<bool, 3>{true, true, false});
    CHECK(gl.dims[0] == 3);
    CHECK(gl.dims[1] == 3);
    CHECK(gl.level >= 5);
    CHECK_THROWS_AS(make_binning_grid(std::vector<Vec3>(5, Vec3{1, 2, 3})), InvalidArgument);
    CHECK_THROWS_AS(make_binning_grid(std::vector<Vec3>{}), InvalidArgument);
}

TEST_CASE("binning grid: --max-cells coarsens the level and says so", "[kernels][scattered]") {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> p;
    for (int i = 0; i < 20000; ++i) p.push_back({u(rng), u(rng), u(rng)});
    const BinningGrid full = make_binning_grid(p);
    CHECK(full.level == 4);  // the dissertation's buckyball: 20,000 uniform samples, 4,096 cells
    CHECK_FALSE(full.coarsened);
    BinningGridParams bp;
    bp.max_cells = 1000;
    const BinningGrid g = make_binning_grid(p, bp);
    CHECK(g.level == 3);  // 10^3 cells
    CHECK(g.rule_level == 4);
    CHECK(g.coarsened);
    CHECK(g.cell_count() <= 1000);
    bp.max_cells = 27;
    CHECK(make_binning_grid(p, bp).level == 0);
    bp.max_cells = 26;
    CHECK_THROWS_AS(make_binning_grid(p, bp), InvalidArgument);
}
