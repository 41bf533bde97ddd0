// `meshless sample` (volume -> scattered points, trilinear values) and `meshless info` on point sets.
#include <catch2/catch.hpp>

#include <cmath>

#include "cli_harness.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/point_set.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

// A linear field v = 2i + 3j - k + 10 on a 6x5x4 uint8 grid with spacing 0.5,1,2: trilinear
// interpolation reproduces it exactly, so every sampled value is checkable.
void write_linear_volume(const TempDir& d) {
    std::string b;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 6; ++i) b.push_back(static_cast<char>(2 * i + 3 * j - k + 10));
    spit(d / "lin_6x5x4_uint8.raw", b);
}

}  // namespace

TEST_CASE("sample: uniform points in the bounds, trilinear values, PLY and CSV, deterministic", "[scatter][cli]") {
    TempDir d("sample-cli");
    write_linear_volume(d);
    const std::string vol = (d / "lin_6x5x4_uint8.raw").string();
    const std::string sp = " --spacing 0.5,1,2";
    REQUIRE(sh("MESHLESS sample " + vol + sp + " --count 500 --seed 7 -o " + (d / "a.ply").string(), d).code == 0);
    REQUIRE(sh("MESHLESS sample " + vol + sp + " --count 500 --seed 7 -o " + (d / "a.csv").string(), d).code == 0);
    REQUIRE(sh("MESHLESS sample " + vol + sp + " --count 500 --seed 7 -o " + (d / "b.csv").string(), d).code == 0);
    REQUIRE(sh("MESHLESS sample " + vol + sp + " --count 500 --seed 8 -o " + (d / "c.csv").string(), d).code == 0);
    CHECK(slurp(d / "a.csv") == slurp(d / "b.csv"));
    CHECK(slurp(d / "a.csv") != slurp(d / "c.csv"));
    CHECK(slurp(d / "a.csv").rfind("x,y,z,value\n", 0) == 0);
    const PointSet ply = read_point_set((d / "a.ply").string());
    const PointSet csv = read_point_set((d / "a.csv").string());
    REQUIRE(ply.size() == 500);
    REQUIRE(csv.size() == 500);
    CHECK(ply.value_name == "value");
    for (std::size_t n = 0; n < 500; ++n) {
        const Vec3 p = ply.pos[n];
        CHECK(p.x == csv.pos[n].x);
        CHECK(p.z == csv.pos[n].z);
        REQUIRE(p.x >= 0);
        REQUIRE(p.x <= 2.5);
        REQUIRE(p.y <= 4);
        REQUIRE(p.z <= 6);
        const double i = p.x / 0.5, j = p.y, k = p.z / 2;
        REQUIRE(ply.value[n] == Approx(2 * i + 3 * j - k + 10).margin(1e-9));
    }
    // uniform: each half of the box along x holds about half of the points
    std::size_t left = 0;
    for (const auto& p : ply.pos) left += p.x < 1.25;
    CHECK(left > 200);
    CHECK(left < 300);
}

TEST_CASE("sample: usage errors and bad volumes leave no output", "[scatter][cli]") {
    TempDir d("sample-cli-bad");
    write_linear_volume(d);
    const std::string vol = (d / "lin_6x5x4_uint8.raw").string();
    const std::string out = (d / "o.ply").string();
    CHECK(sh("MESHLESS sample " + vol + " -o " + out, d).code == 1);
    CHECK(sh("MESHLESS sample " + vol + " --count 0 -o " + out, d).code == 1);
    CHECK(sh("MESHLESS sample " + vol + " --count 10", d).code == 1);
    CHECK(sh("MESHLESS sample " + vol + " --count 10 -o " + (d / "o.xyz").string(), d).code == 1);
    // a .txt was silently CSV and a .vtp refused; now .txt is refused like any other name and .vtp
    // is VTK XML PolyData with one vertex cell per point
    const auto txt = sh("MESHLESS sample " + vol + " --count 10 -o " + (d / "o.txt").string(), d);
    CHECK(txt.code == 1);
    CHECK(txt.err.find("this output is a point set with values, written to a .ply (binary PLY), .csv or .vtp") != std::string::npos);
    CHECK(!std::filesystem::exists(d / "o.txt"));
    REQUIRE(sh("MESHLESS sample " + vol + " --count 10 -o " + (d / "o.vtp").string(), d).code == 0);
    const std::string vtp = slurp(d / "o.vtp");
    CHECK(vtp.find("NumberOfPoints=\"10\"") != std::string::npos);
    CHECK(vtp.find("NumberOfVerts=\"10\"") != std::string::npos);
    spit(d / "bad_6x5x4_uint8.raw", "short");
    const auto r = sh("MESHLESS sample " + (d / "bad_6x5x4_uint8.raw").string() + " --count 10 -o " + out, d);
    CHECK(r.code == 2);
    CHECK(!std::filesystem::exists(out));
}

TEST_CASE("info: point sets show points, blocks, value range, bounds and dropped samples", "[scatter][cli]") {
    TempDir d("info-ps");
    spit(d / "p.csv", "x,y,z,t\n0,0,0,1\n1,0,0,2\n0,1,0,3\n0,0,1,4\nnan,0,0,5\n");
    auto r = sh("MESHLESS info " + (d / "p.csv").string(), d);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("text point set") != std::string::npos);
    CHECK(r.out.find("points: 4") != std::string::npos);
    CHECK(r.out.find("value: t, range 1 .. 4") != std::string::npos);
    CHECK(r.out.find("dropped: 1 NaN/Inf") != std::string::npos);
    r = sh("MESHLESS info --strict " + (d / "p.csv").string(), d);
    CHECK(r.code == 2);
    CHECK(r.err.find("line 6") != std::string::npos);
    if (!have_shared_data()) return;
    const std::string p3 = (shared_data() / "plot3d").string();
    r = sh("MESHLESS info " + p3 + "/combxyz.bin " + p3 + "/multi-bin.xyz " + (shared_data() / "scattered/Particles.raw").string(), d);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("points: 47025") != std::string::npos);
    CHECK(r.out.find("57 x 33 x 25") != std::string::npos);
    CHECK(r.out.find("value: density") != std::string::npos);
    CHECK(r.out.find("grid 2: 8 x 12 x 12") != std::string::npos);
    CHECK(r.out.find("points: 197") != std::string::npos);
    r = sh("MESHLESS info " + p3 + "/bluntfinxyz.bin", d);
    CHECK(r.code == 2);
    CHECK(r.err.find("484 trailing bytes") != std::string::npos);
    r = sh("MESHLESS info --allow-trailing " + p3 + "/bluntfinxyz.bin", d);
    CHECK(r.code == 0);
    CHECK(r.out.find("40 x 32 x 32") != std::string::npos);
    CHECK(r.out.find("484 bytes after the q data ignored") != std::string::npos);
}

TEST_CASE("info on a PLY point set: count, bounds, the range of every property, non-finite values", "[scatter][cli]") {
    TempDir d("info-ply");
    spit(d / "p.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "property float value\nend_header\n1 -2 3 nan\n4 5 -6 7\n-0.5 0 0.25 -1.5\n");
    const auto r = sh("MESHLESS info " + (d / "p.ply").string(), d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("3 vertices"));
    CHECK_THAT(r.out, Catch::Contains("bounds: x -0.5 .. 4, y -2 .. 5, z -6 .. 3"));
    CHECK_THAT(r.out, Catch::Contains("value: -1.5 .. 7"));
    CHECK_THAT(r.out, Catch::Contains("non-finite values: 1"));
    CHECK_THAT(r.out, Catch::Contains("element vertex 3"));
    // a body shorter than the header claims is still refused
    spit(d / "short.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n");
    const auto s = sh("MESHLESS info " + (d / "short.ply").string(), d);
    CHECK(s.code == 2);
    CHECK_THAT(s.err, Catch::Contains("short.ply"));
}
