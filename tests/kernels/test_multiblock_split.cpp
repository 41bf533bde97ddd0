// The layouts of `meshless split` (kernels/multiblock_split.hpp) against their definitions: nodes
// that are the volume's carry its values, resampled nodes of a linear field carry the field
// exactly (trilinear reproduces linear functions), blocks share exactly the documented node planes,
// twisted grids have no inverted cells, and the AMR hierarchy nests and covers the isosurface.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "kernels/analytic_volumes.hpp"
#include "kernels/errors.hpp"
#include "kernels/multiblock_split.hpp"

using namespace meshless;

namespace {

/// f = 1 + 2x + 3y - z on an nx x ny x nz float32 grid, origin (0.5, -1, 2), spacing (0.5, 0.25, 1).
Volume linear_volume(std::int64_t nx, std::int64_t ny, std::int64_t nz) {
    GridSpec g;
    g.dims = {nx, ny, nz};
    g.origin = {0.5, -1, 2};
    g.spacing = {0.5, 0.25, 1};
    Volume v(g, SampleType::f32);
    float* d = reinterpret_cast<float*>(v.bytes.data());
    for (std::int64_t k = 0; k < nz; ++k)
        for (std::int64_t j = 0; j < ny; ++j)
            for (std::int64_t i = 0; i < nx; ++i) {
                const double x = 0.5 + 0.5 * i, y = -1 + 0.25 * j, z = 2.0 + k;
                d[g.index(i, j, k)] = static_cast<float>(1 + 2 * x + 3 * y - z);
            }
    return v;
}
double linear(const Vec3& p) { return 1 + 2 * p.x + 3 * p.y - p.z; }

using Key = std::tuple<double, double, double>;
Key key(const Vec3& p) { return {p.x, p.y, p.z}; }

/// position -> value of every volume node
std::map<Key, double> volume_nodes(const Volume& v) {
    std::map<Key, double> m;
    const auto& g = v.grid;
    for (std::int64_t k = 0; k < g.dims[2]; ++k)
        for (std::int64_t j = 0; j < g.dims[1]; ++j)
            for (std::int64_t i = 0; i < g.dims[0]; ++i)
                m[{g.origin[0] + i * g.spacing[0], g.origin[1] + j * g.spacing[1], g.origin[2] + k * g.spacing[2]}] =
                    v.view().at(i, j, k);
    return m;
}

}  // namespace

TEST_CASE("split overlapping: the volume's nodes, neighbours share overlap+1 node planes", "[split]") {
    // longest world axis: x (41 * 0.5 = 20 vs 17 * 0.25, 9 * 1)
    const Volume v = linear_volume(41, 18, 10);
    const auto nodes = volume_nodes(v);
    for (int ov : {0, 2, 3}) {
        SplitParams p;
        p.blocks = 3;
        p.overlap = ov;
        const Multiblock mb = split_volume(v.view(), SplitLayout::overlapping, p);
        REQUIRE(mb.blocks.size() == 3);
        std::set<Key> seen;
        std::vector<std::set<double>> xs(3);
        for (std::size_t b = 0; b < 3; ++b) {
            const auto& blk = mb.blocks[b];
            CHECK(blk.dims[1] == 18);
            CHECK(blk.dims[2] == 10);
            for (std::size_t n = 0; n < blk.node.size(); ++n) {
                const auto it = nodes.find(key(blk.node[n]));
                REQUIRE(it != nodes.end());
                REQUIRE(blk.value[n] == it->second);
                seen.insert(key(blk.node[n]));
                xs[b].insert(blk.node[n].x);
            }
        }
        CHECK(seen.size() == nodes.size());  // every node in some block
        for (int b = 0; b < 2; ++b) {
            std::size_t shared = 0;
            for (double x : xs[b]) shared += xs[b + 1].count(x);
            CHECK(shared == static_cast<std::size_t>(ov + 1));
        }
    }
    SplitParams bad;
    bad.blocks = 30;
    CHECK_THROWS_AS(split_volume(v.view(), SplitLayout::overlapping, bad), InvalidArgument);
    bad.blocks = 2;
    bad.overlap = 40;
    CHECK_THROWS_AS(split_volume(v.view(), SplitLayout::overlapping, bad), InvalidArgument);
    CHECK_THROWS_AS(split_volume(linear_volume(2, 5, 5).view(), SplitLayout::overlapping), InvalidArgument);
}

TEST_CASE("split semi-conforming: half resolution beyond the plane, every second node shared", "[split]") {
    const Volume v = linear_volume(33, 17, 9);  // x cells 32: plane at m = 16
    const auto nodes = volume_nodes(v);
    const Multiblock mb = split_volume(v.view(), SplitLayout::semi_conforming);
    REQUIRE(mb.blocks.size() == 2);
    const auto& a = mb.blocks[0];
    const auto& b = mb.blocks[1];
    CHECK(a.dims == std::array<std::int64_t, 3>{17, 17, 9});
    CHECK(b.dims == std::array<std::int64_t, 3>{9, 9, 5});
    for (const auto* blk : {&a, &b})
        for (std::size_t n = 0; n < blk->node.size(); ++n) {
            const auto it = nodes.find(key(blk->node[n]));
            REQUIRE(it != nodes.end());
            REQUIRE(blk->value[n] == it->second);
        }
    // the shared face x = 0.5 + 16 * 0.5: a has 17 x 9 nodes there, b 9 x 5, all of b's among a's
    const double xm = 0.5 + 16 * 0.5;
    std::set<Key> fa, fb;
    for (const auto& p : a.node)
        if (p.x == xm) fa.insert(key(p));
    for (const auto& p : b.node)
        if (p.x == xm) fb.insert(key(p));
    CHECK(fa.size() == 17 * 9);
    CHECK(fb.size() == 9 * 5);
    for (const auto& k : fb) CHECK(fa.count(k) == 1);
}

TEST_CASE("split non-conforming and rotated: resampled nodes carry the field, no shared nodes, no inverted cell", "[split]") {
    const Volume v = linear_volume(41, 18, 10);
    const auto nodes = volume_nodes(v);
    SECTION("non-conforming") {
        const Multiblock mb = split_volume(v.view(), SplitLayout::non_conforming);
        REQUIRE(mb.blocks.size() == 2);
        const auto& b = mb.blocks[1];
        std::size_t coincide = 0, face = 0;
        const double xm = b.node[0].x;
        CHECK(xm == 0.5 + 20 * 0.5);
        for (std::size_t n = 0; n < b.node.size(); ++n) {
            REQUIRE(b.value[n] == Approx(linear(b.node[n])).margin(1e-4));
            if (b.node[n].x == xm) {
                ++face;
                coincide += nodes.count(key(b.node[n]));
            }
        }
        CHECK(face == static_cast<std::size_t>(b.dims[1] * b.dims[2]));
        CHECK(coincide < face / 4);  // only where the two lattices happen to meet (corners, edges)
    }
    SECTION("rotated") {
        const Multiblock mb = split_volume(v.view(), SplitLayout::rotated);
        REQUIRE(mb.blocks.size() == 2);
        for (const auto& b : mb.blocks) {
            std::size_t moved = 0;
            for (std::size_t n = 0; n < b.node.size(); ++n) {
                REQUIRE(b.value[n] == Approx(linear(b.node[n])).margin(1e-4));
                moved += nodes.count(key(b.node[n])) == 0;
            }
            CHECK(moved > b.node.size() * 9 / 10);
            // every hexahedron positively oriented at its 8 corners
            for (std::int64_t k = 0; k + 1 < b.dims[2]; ++k)
                for (std::int64_t j = 0; j + 1 < b.dims[1]; ++j)
                    for (std::int64_t i = 0; i + 1 < b.dims[0]; ++i)
                        for (int c = 0; c < 8; ++c) {
                            const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
                            const Vec3 o = b.node[b.index(i + di, j + dj, k + dk)];
                            const Vec3 ex = b.node[b.index(i + 1 - di, j + dj, k + dk)] - o;
                            const Vec3 ey = b.node[b.index(i + di, j + 1 - dj, k + dk)] - o;
                            const Vec3 ez = b.node[b.index(i + di, j + dj, k + 1 - dk)] - o;
                            const double sgn = ((di + dj + dk) % 2) ? -1 : 1;
                            REQUIRE(sgn * dot(cross(ex, ey), ez) > 0);
                        }
        }
    }
}

TEST_CASE("split amr: linear fields exact at cell centres, boxes nest, the isosurface is refined", "[split]") {
    SECTION("linear field, middle halves") {
        const Volume v = linear_volume(33, 33, 17);
        const AmrHierarchy h = split_amr(v.view());
        REQUIRE(h.boxes.size() == 3);
        CHECK(h.boxes[0].cells() == std::array<std::int64_t, 3>{8, 8, 4});
        CHECK(h.spacing(2)[0] == 0.5);
        const Multiblock mb = amr_to_multiblock(h);
        for (const auto& b : mb.blocks) {
            CHECK(b.cell_centred);
            for (std::size_t n = 0; n < b.node.size(); ++n) REQUIRE(b.value[n] == Approx(linear(b.node[n])).margin(1e-4));
        }
        // level 1 = finest cells [8, 24) along x: level-1 cells [4, 11]; level 2 = [12, 20)
        CHECK(h.boxes[1].lo[0] == 4);
        CHECK(h.boxes[1].hi[0] == 11);
        CHECK(h.boxes[2].lo[0] == 12);
        CHECK(h.boxes[2].hi[0] == 19);
    }
    SECTION("sphere with iso: every dual cell of the finest lattice that crosses iso lies in level-2 boxes") {
        const Volume v = make_analytic_volume(AnalyticField::sphere, 81);
        AmrParams p;
        p.iso = 0.7;
        p.tile = 4;
        const AmrHierarchy h = split_amr(v.view(), p);
        const std::int64_t F = 80;
        std::vector<double> fine(F * F * F, NAN);
        std::vector<std::uint8_t> in2(F * F * F, 0), in1(F * F * F, 0);
        for (const AmrBox& b : h.boxes) {
            const std::int64_t s = std::int64_t{1} << (2 - b.level);
            const auto n = b.cells();
            for (std::int64_t k = b.lo[2] * s; k < (b.hi[2] + 1) * s; ++k)
                for (std::int64_t j = b.lo[1] * s; j < (b.hi[1] + 1) * s; ++j)
                    for (std::int64_t i = b.lo[0] * s; i < (b.hi[0] + 1) * s; ++i) {
                        const std::size_t f = static_cast<std::size_t>(i + F * (j + F * k));
                        if (b.level == 1) in1[f] = 1;
                        if (b.level == 2) {
                            in2[f] = 1;
                            fine[f] = b.value[static_cast<std::size_t>((i - b.lo[0]) + n[0] * ((j - b.lo[1]) + n[1] * (k - b.lo[2])))];
                        }
                    }
        }
        std::size_t crossing = 0;
        std::vector<double> mean(F * F * F);
        for (std::int64_t k = 0; k < F; ++k)
            for (std::int64_t j = 0; j < F; ++j)
                for (std::int64_t i = 0; i < F; ++i) {
                    double s = 0;
                    for (int c = 0; c < 8; ++c) s += v.view().at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                    mean[i + F * (j + F * k)] = s / 8;
                }
        for (std::size_t f = 0; f < in2.size(); ++f) {
            if (in2[f]) {
                REQUIRE(in1[f]);                    // nesting
                REQUIRE(fine[f] == mean[f]);        // finest cell = mean of its corners
            }
        }
        for (std::int64_t k = 0; k + 1 < F; ++k)
            for (std::int64_t j = 0; j + 1 < F; ++j)
                for (std::int64_t i = 0; i + 1 < F; ++i) {
                    double lo = INFINITY, hi = -INFINITY;
                    for (int c = 0; c < 8; ++c) {
                        const double m = mean[(i + (c & 1)) + F * ((j + ((c >> 1) & 1)) + F * (k + ((c >> 2) & 1)))];
                        lo = std::min(lo, m), hi = std::max(hi, m);
                    }
                    if (!(lo < 0.7 && 0.7 < hi)) continue;
                    ++crossing;
                    for (int c = 0; c < 8; ++c)
                        REQUIRE(in2[(i + (c & 1)) + F * ((j + ((c >> 1) & 1)) + F * (k + ((c >> 2) & 1)))]);
                }
        CHECK(crossing > 1000);
        // and refinement is local: level 2 covers well under the whole domain
        std::size_t n2 = 0;
        for (auto x : in2) n2 += x;
        CHECK(n2 < in2.size() * 6 / 10);
    }
    CHECK_THROWS_AS(split_amr(linear_volume(4, 9, 9).view()), InvalidArgument);
}

TEST_CASE("resample_volume keeps the corners and reproduces linear fields", "[split]") {
    const Volume v = linear_volume(41, 18, 10);
    const Volume r = resample_volume(v.view(), 21);
    // extents 20 x 4.25 x 9 world units: 20 cells along x, round(20 * 4.25 / 20) = 4, round(9) = 9
    CHECK(r.grid.dims == std::array<std::int64_t, 3>{21, 5, 10});
    CHECK(r.grid.spacing[1] == 4.25 / 4);
    for (std::int64_t k = 0; k < 10; ++k)
        for (std::int64_t j = 0; j < 5; ++j)
            for (std::int64_t i = 0; i < 21; ++i) {
                const Vec3 p{0.5 + i * r.grid.spacing[0], -1 + j * r.grid.spacing[1], 2 + k * r.grid.spacing[2]};
                REQUIRE(r.view().at(i, j, k) == Approx(linear(p)).margin(1e-4));
            }
    CHECK_THROWS_AS(resample_volume(v.view(), 1), InvalidArgument);
    CHECK_THROWS_AS(resample_volume(linear_volume(9, 9, 9).view(), 4096), InvalidArgument);  // 2^36 samples
}
