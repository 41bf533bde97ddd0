// Tests for kernels/hex_marching_cubes.hpp: exact planar cuts (area, orientation) on axis-aligned and
// sheared cells, winding flip, Jacobian signs of boxes, mirrored, collapsed and inverted cells.
#include <catch2/catch.hpp>

#include <cmath>

#include "kernels/hex_marching_cubes.hpp"

using namespace meshless;

namespace {

HexCell unit_cell(Vec3 lo, Vec3 size, double (*f)(const Vec3&)) {
    HexCell c;
    for (int i = 0; i < 8; ++i) {
        c.corner[static_cast<std::size_t>(i)] = {lo.x + size.x * (i & 1), lo.y + size.y * ((i >> 1) & 1), lo.z + size.z * ((i >> 2) & 1)};
        c.value[static_cast<std::size_t>(i)] = f(c.corner[static_cast<std::size_t>(i)]);
    }
    return c;
}

}  // namespace

TEST_CASE("hex marching cubes: a plane x = 0.3 through an axis-aligned cell gives its exact cut, normals along -x", "[hex_mc]") {
    const HexCell c = unit_cell({0, 0, 0}, {1, 2, 3}, [](const Vec3& p) { return p.x; });
    std::array<HexTriangle, kMcMaxTriangles> t;
    const int n = hex_marching_cubes(c, 0.3, false, t);
    REQUIRE(n == 2);
    double area = 0;
    for (int i = 0; i < n; ++i) {
        for (const auto& v : t[static_cast<std::size_t>(i)].v) CHECK_THAT(v.x, Catch::WithinAbs(0.3, 1e-15));
        const Vec3 nrm = cross(t[static_cast<std::size_t>(i)].v[1] - t[static_cast<std::size_t>(i)].v[0],
                               t[static_cast<std::size_t>(i)].v[2] - t[static_cast<std::size_t>(i)].v[0]);
        CHECK(nrm.x < 0);  // towards decreasing values (VTK's convention)
        area += 0.5 * norm(nrm);
    }
    CHECK_THAT(area, Catch::WithinRel(6.0, 1e-12));
    // Flipped winding for a left-handed block.
    std::array<HexTriangle, kMcMaxTriangles> f;
    REQUIRE(hex_marching_cubes(c, 0.3, true, f) == 2);
    CHECK(cross(f[0].v[1] - f[0].v[0], f[0].v[2] - f[0].v[0]).x > 0);
}

TEST_CASE("hex marching cubes: crossings on a sheared cell lie on its edges, no sign change gives no triangle", "[hex_mc]") {
    HexCell c = unit_cell({0, 0, 0}, {1, 1, 1}, [](const Vec3& p) { return p.z; });
    for (int i = 4; i < 8; ++i) c.corner[static_cast<std::size_t>(i)].x += 0.5;  // shear the top face
    std::array<HexTriangle, kMcMaxTriangles> t;
    REQUIRE(hex_marching_cubes(c, 0.5, false, t) == 2);
    for (int i = 0; i < 2; ++i)
        for (const auto& v : t[static_cast<std::size_t>(i)].v) {
            CHECK_THAT(v.z, Catch::WithinAbs(0.5, 1e-15));
            CHECK((std::abs(v.x - 0.25) < 1e-15 || std::abs(v.x - 1.25) < 1e-15));
        }
    CHECK(hex_marching_cubes(c, 2.0, false, t) == 0);
    CHECK(hex_marching_cubes(c, -1.0, false, t) == 0);
}

TEST_CASE("hex jacobian range: positive for a box, negative when mirrored, zero when collapsed, mixed when inverted", "[hex_mc]") {
    const HexCell box = unit_cell({0, 0, 0}, {1, 2, 3}, [](const Vec3&) { return 0.0; });
    auto r = hex_jacobian_range(box.corner);
    CHECK_THAT(r[0], Catch::WithinRel(6.0, 1e-12));
    CHECK_THAT(r[1], Catch::WithinRel(6.0, 1e-12));
    auto mirrored = box.corner;
    for (auto& p : mirrored) p.x = -p.x;
    r = hex_jacobian_range(mirrored);
    CHECK(r[1] < 0);
    auto collapsed = box.corner;
    for (int i = 4; i < 8; ++i) collapsed[static_cast<std::size_t>(i)].z = 0;  // top face onto the bottom
    r = hex_jacobian_range(collapsed);
    CHECK(r[0] == 0);
    auto inverted = box.corner;
    inverted[7] = {-1, -1, -1};  // one corner pulled through the cell
    r = hex_jacobian_range(inverted);
    CHECK(r[0] < 0);
    CHECK(r[1] > 0);
}
