// `meshless split` as users run it: the dissertation's multiblock sets in one command each (bucky as
// two semi-conforming grids = Table 4.1's 21,114 nodes with --resample 33, neghip as two
// overlapping, fuel as five overlapping), the AMR layout, and bad command lines (exit 1) and bad
// inputs (exit 2) leaving nothing behind.
#include <catch2/catch.hpp>

#include <filesystem>

#include "cli_harness.hpp"

using namespace meshless::test;
namespace fs = std::filesystem;

TEST_CASE("split: bucky, neghip and fuel as the dissertation's multiblock sets", "[split_cli]") {
    if (!have_shared_data()) {
        WARN("shared data not found: skipped");
        return;
    }
    TempDir dir("split-real");
    const std::string data = shared_data().string();
    auto r = sh("cd '" + dir.path.string() + "' && MESHLESS split '" + data +
                    "/bucky/Bucky_32x32x32_uint8.raw' --layout semi-conforming --resample 33 -o bucky.vtm",
                dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("17x33x33") != std::string::npos);
    CHECK(r.out.find("9x17x17") != std::string::npos);
    CHECK(r.out.find("21114 nodes in all") != std::string::npos);
    CHECK(fs::exists(dir / "bucky/bucky_0.vts"));
    CHECK(fs::exists(dir / "bucky/bucky_1.vts"));
    r = sh("MESHLESS split '" + data + "/neghip/neghip_64x64x64_uint8.raw' --layout overlapping -o '" +
               (dir / "neghip.vtm").string() + "'",
           dir);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("wrote") != std::string::npos);
    CHECK(fs::exists(dir / "neghip/neghip_1.vts"));
    r = sh("MESHLESS split '" + data + "/fuel/fuel_64x64x64_uint8.raw' --layout overlapping --blocks 5 -o '" +
               (dir / "fuel.vtm").string() + "'",
           dir);
    REQUIRE(r.code == 0);
    CHECK(fs::exists(dir / "fuel/fuel_4.vts"));
    CHECK(!fs::exists(dir / "fuel/fuel_5.vts"));
    r = sh("MESHLESS split '" + data + "/fuel/fuel_64x64x64_uint8.raw' --layout amr --iso 100 -o '" +
               (dir / "fuel.vthb").string() + "'",
           dir);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("level 2:") != std::string::npos);
    CHECK(fs::exists(dir / "fuel/fuel_0.vti"));
}

TEST_CASE("split: bad command lines exit 1, bad inputs exit 2, nothing written", "[split_cli]") {
    TempDir dir("split-bad");
    const std::string vol = write_uint8_analytic_volume(dir, "s", meshless::AnalyticField::sphere, 17, 200, 0);
    const std::string o = (dir / "o.vtm").string();
    CHECK(sh("MESHLESS split '" + vol + "' --layout diagonal -o '" + o + "'", dir).code == 1);
    CHECK(sh("MESHLESS split '" + vol + "' --layout amr -o '" + o + "'", dir).code == 1);         // amr writes .vthb
    CHECK(sh("MESHLESS split '" + vol + "' --layout overlapping -o '" + (dir / "o.vthb").string() + "'", dir).code == 1);
    CHECK(sh("MESHLESS split '" + vol + "' --layout semi-conforming --blocks 3 -o '" + o + "'", dir).code == 1);
    CHECK(sh("MESHLESS split '" + vol + "' --layout overlapping --iso 3 -o '" + o + "'", dir).code == 1);
    CHECK(sh("MESHLESS split '" + vol + "' --layout overlapping -o '" + o + "'", dir).code == 0);
    fs::remove_all(dir / "o");
    fs::remove(o);
    const auto r = sh("MESHLESS split '" + (dir / "missing_8x8x8_uint8.raw").string() + "' --layout overlapping -o '" + o + "'", dir);
    CHECK(r.code == 2);
    CHECK(r.err.find("missing_8x8x8_uint8.raw") != std::string::npos);
    // too many blocks for the volume: a data error naming the problem
    const auto r2 = sh("MESHLESS split '" + vol + "' --layout overlapping --blocks 12 -o '" + o + "'", dir);
    CHECK(r2.code != 0);
    CHECK(r2.err.find("blocks") != std::string::npos);
    CHECK(!fs::exists(o));
}
