// kernels/mesh_normals.hpp: area-weighted vertex normals against an oracle (the marching cubes'
// own gradient normals on an analytic sphere), orientation, degenerate input.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include "kernels/analytic_volumes.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/mesh_normals.hpp"

using namespace meshless;

TEST_CASE("area-weighted normals agree with the gradient normals on a sphere and point toward decreasing value", "[mesh_normals]") {
    const Volume v = make_analytic_volume(AnalyticField::sphere, 32);
    const Mesh m = marching_cubes(v.view(), 0.5);
    REQUIRE(m.triangle_count() > 1000);
    const std::vector<float> n = area_weighted_normals(m);
    REQUIRE(n.size() == m.normals.size());
    std::size_t close = 0;
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
        double dot = 0, len = 0;
        for (int a = 0; a < 3; ++a) {
            dot += double(n[3 * i + a]) * m.normals[3 * i + a];
            len += double(n[3 * i + a]) * n[3 * i + a];
        }
        CHECK(std::fabs(len - 1) < 1e-5);
        close += dot > 0.98;  // the gradient normals point toward decreasing value (VTK's convention)
    }
    CHECK(close >= m.vertex_count() * 99 / 100);
}

TEST_CASE("area-weighted normals of an isolated vertex are zero and bad indices are refused", "[mesh_normals]") {
    Mesh m;
    m.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5};
    m.tri = {0, 1, 2};
    const std::vector<float> n = area_weighted_normals(m);
    REQUIRE(n.size() == 12);
    for (int v = 0; v < 3; ++v) CHECK(n[3 * v + 2] == 1.0f);  // counter-clockwise seen from +z
    CHECK(n[9] == 0.0f);
    CHECK(n[10] == 0.0f);
    CHECK(n[11] == 0.0f);
    m.tri = {0, 1, 4};
    CHECK_THROWS_AS(area_weighted_normals(m), std::out_of_range);
}
