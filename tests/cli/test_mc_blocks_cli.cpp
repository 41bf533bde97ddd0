// `meshless mc BLOCKS...` (the naive per-block marching cubes) end to end on the combustor's three
// .vts blocks of ../shared/data (skipped with a warning when it is absent): identical bytes for
// any --threads, a per-face block property, the --stats lines, an isovalue outside the data.
#include <catch2/catch.hpp>

#include <algorithm>

#include "cli/cli_harness.hpp"
#include "formats/ply_mesh.hpp"

using namespace meshless;
using namespace meshless::test;

TEST_CASE("mc on multiblock .vts: same bytes for any --threads, block ids, stats", "[cli][real][block_mc]") {
    if (!have_shared_data()) {
        WARN("../shared/data absent: naive multiblock mc test skipped");
        return;
    }
    TempDir d("mc-blocks");
    const std::string P = (shared_data() / "plot3d").string() + "/";
    const std::string blocks = P + "multicomb_0.vts " + P + "multicomb_1.vts " + P + "multicomb_2.vts";
    const std::string D = d.path.string() + "/";
    const auto r1 = sh("MESHLESS mc " + blocks + " --iso 0.4 -o " + D + "t1.ply --threads 1 --stats", d);
    REQUIRE(r1.code == 0);
    CHECK(r1.err.find("3 block(s)") != std::string::npos);
    CHECK(r1.err.find("crack edges") != std::string::npos);
    CHECK(r1.err.find("intersecting") != std::string::npos);
    REQUIRE(sh("MESHLESS mc " + blocks + " --iso 0.4 -o " + D + "t2.ply --threads 2", d).code == 0);
    REQUIRE(sh("MESHLESS mc " + blocks + " --iso 0.4 -o " + D + "t4.ply --threads 4", d).code == 0);
    const std::string bytes = slurp(d / "t1.ply");
    CHECK(bytes == slurp(d / "t2.ply"));
    CHECK(bytes == slurp(d / "t4.ply"));
    CHECK(bytes.find("property uint block") != std::string::npos);
    // the .vtp carries per-point Normals (area-weighted within each block) beside the cells' block ids
    REQUIRE(sh("MESHLESS mc " + blocks + " --iso 0.4 -o " + D + "t.vtp", d).code == 0);
    const std::string vtp = slurp(d / "t.vtp");
    CHECK(vtp.find("<PointData Normals=\"Normals\">") != std::string::npos);
    CHECK(vtp.find("Name=\"block\"") != std::string::npos);
    const Mesh m = read_ply_mesh((d / "t1.ply").string());
    REQUIRE(m.block.size() == m.triangle_count());
    std::size_t seen[3] = {0, 0, 0};
    for (auto b : m.block) {
        REQUIRE(b < 3);
        ++seen[b];
    }
    CHECK(seen[0] > 0);
    CHECK(seen[1] > 0);
    CHECK(seen[2] > 0);

    // a multi-grid PLOT3D file: one block per grid, q's density
    const auto p3d = sh("MESHLESS mc " + P + "multi-bin.xyz --iso 0.4 -o " + D + "p3d.ply --stats --threads 2", d);
    REQUIRE(p3d.code == 0);
    CHECK(p3d.err.find("2 block(s)") != std::string::npos);
    const Mesh pm = read_ply_mesh((d / "p3d.ply").string());
    CHECK(pm.triangle_count() > 0);
    CHECK(std::count(pm.block.begin(), pm.block.end(), 1u) > 0);

    // an isovalue outside every block's range: a warning and a valid empty mesh
    const auto r = sh("MESHLESS mc " + blocks + " --iso 99 -o " + D + "empty.ply", d);
    CHECK(r.code == 0);
    CHECK(r.err.find("99") != std::string::npos);
    CHECK(read_ply_mesh((d / "empty.ply").string()).triangle_count() == 0);
    // a missing block file: a data/IO error naming it, nothing written
    const auto bad = sh("MESHLESS mc " + blocks + " " + P + "no_such.vts --iso 0.4 -o " + D + "bad.ply", d);
    CHECK(bad.code == 2);
    CHECK(bad.err.find("no_such.vts") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(d / "bad.ply"));
}
