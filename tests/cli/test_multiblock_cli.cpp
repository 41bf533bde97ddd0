// `meshless isosurface BLOCKS...` and its pipes (generate BLOCKS | project --field KIND BLOCKS | write /
// splat) as a user runs them, on two overlapping PLOT3D blocks of a sampled sphere written by the
// test: identical bytes in-process and across pipes for any --threads, the PLY `block` property with
// both blocks present, points on the sphere, --stats counts, the out-of-range warning with empty
// valid outputs, and the mistakes a user can make with seed streams. With the shared data: the
// three combustor .vts pieces, in-process vs pipes.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>

#include "cli/cli_harness.hpp"
#include "formats/ply_points.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

/// Two overlapping blocks of |p| as ASCII PLOT3D (spheres.xyz + spheres.q, density = |p|):
/// block 0: [-1, 0.25] x [-1, 1]^2 at h = 0.125, block 1: [-0.25, 1] x [-1, 1]^2 at h = 0.2, sheared.
std::string write_sphere_blocks(const TempDir& d) {
    struct B {
        int ni, nj, nk;
        double x0, hx, h;
        double shear;
    };
    const B blocks[2] = {{11, 17, 17, -1.0, 0.125, 0.125, 0.0}, {8, 11, 11, -0.25, 1.25 / 7, 0.2, 0.03}};
    std::string xyz = "2\n", q = "2\n";
    for (const B& b : blocks) {
        xyz += std::to_string(b.ni) + " " + std::to_string(b.nj) + " " + std::to_string(b.nk) + "\n";
        q += std::to_string(b.ni) + " " + std::to_string(b.nj) + " " + std::to_string(b.nk) + "\n";
    }
    char buf[64];
    for (const B& b : blocks) {
        std::vector<double> coord[3], rho;
        for (int k = 0; k < b.nk; ++k)
            for (int j = 0; j < b.nj; ++j)
                for (int i = 0; i < b.ni; ++i) {
                    const double x = b.x0 + b.hx * i + b.shear * j, y = -1 + b.h * j, z = -1 + b.h * k;
                    coord[0].push_back(x);
                    coord[1].push_back(y);
                    coord[2].push_back(z);
                    rho.push_back(std::sqrt(x * x + y * y + z * z));
                }
        for (const auto& c : coord)
            for (double v : c) {
                std::snprintf(buf, sizeof buf, "%.9g\n", v);
                xyz += buf;
            }
        q += "0.5 0 1000 0\n";
        for (int f = 0; f < 5; ++f)
            for (double v : rho) {
                std::snprintf(buf, sizeof buf, "%.9g\n", f == 0 ? v : 0.0);
                q += buf;
            }
    }
    spit(d / "spheres.xyz", xyz);
    spit(d / "spheres.q", q);
    return (d / "spheres.xyz").string();
}

}  // namespace

TEST_CASE("isosurface BLOCKS: in-process and piped give the same bytes for any --threads", "[cli][multiblock]") {
    TempDir d("mbpipe");
    const std::string xyz = write_sphere_blocks(d);
    const std::string D = d.path.string();
    const std::string common = " --iso 0.6 --field mpu --samples 3";
    auto r = sh("MESHLESS isosurface " + xyz + common + " --threads 1 -o " + D + "/a.ply --png " + D + "/a.png --size 160x160 --stats", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("2 blocks"));
    CHECK_THAT(r.err, Catch::Contains("collapsed/inverted"));
    CHECK_THAT(r.err, Catch::Contains("converged"));
    CHECK_THAT(r.err, Catch::Contains("points/s per core"));
    REQUIRE(sh("MESHLESS isosurface " + xyz + common + " --threads 2 -o " + D + "/b.ply", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + xyz + " --iso 0.6 --samples 3 --threads 2 | MESHLESS project --field mpu " + xyz +
                   " --threads 2 | MESHLESS write -o " + D + "/c.ply",
               d).code == 0);
    REQUIRE(sh("MESHLESS generate " + xyz + " --iso 0.6 --samples 3 --compress -o " + D + "/s.seeds && MESHLESS project --field mpu " +
                   xyz + " -i " + D + "/s.seeds --threads 3 --compress | MESHLESS splat -o " + D + "/c.png --size 160x160",
               d).code == 0);
    const std::string a = slurp(d / "a.ply");
    CHECK(a.size() > 10000);
    CHECK(a == slurp(d / "b.ply"));
    CHECK(a == slurp(d / "c.ply"));
    CHECK(slurp(d / "a.png") == slurp(d / "c.png"));
    // seed streams do not depend on the thread count either
    REQUIRE(sh("MESHLESS generate " + xyz + " --iso 0.6 --threads 1 -o " + D + "/s1 && MESHLESS generate " + xyz +
                   " --iso 0.6 --threads 2 -o " + D + "/s2",
               d).code == 0);
    // (their META frames differ by the producer's command line: compare what follows it)
    auto after_meta = [](const std::string& s) {
        REQUIRE(s.size() > 64);
        const std::size_t meta_bytes = static_cast<unsigned char>(s[56]) | static_cast<unsigned char>(s[57]) << 8 |
                                       static_cast<unsigned char>(s[58]) << 16;
        return s.substr(64 + meta_bytes);
    };
    const std::string s1 = slurp(d / "s1");
    CHECK(s1.substr(0, 32) == slurp(d / "s2").substr(0, 32));
    CHECK(after_meta(s1).size() > 10000);
    CHECK(after_meta(s1) == after_meta(slurp(d / "s2")));
}

TEST_CASE("isosurface BLOCKS with a fitted field (.mlf): in-process, piped and built-in-place give the same bytes", "[cli][multiblock]") {
    TempDir d("mbmlf");
    const std::string xyz = write_sphere_blocks(d);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS fit " + xyz + " --field mpu --threads 2 -o " + D + "/f.mlf", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + xyz + " --iso 0.6 --field " + D + "/f.mlf --threads 1 -o " + D + "/a.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + xyz + " --iso 0.6 --field mpu --threads 2 -o " + D + "/b.ply", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + xyz + " --iso 0.6 --threads 2 | MESHLESS project --field " + D +
                   "/f.mlf --threads 2 | MESHLESS write -o " + D + "/c.ply",
               d).code == 0);
    const std::string a = slurp(d / "a.ply");
    CHECK(a.size() > 10000);
    CHECK(a == slurp(d / "b.ply"));
    CHECK(a == slurp(d / "c.ply"));
    // a .mlf fitted to other data is refused (exit 2) when the blocks are given
    REQUIRE(sh("MESHLESS fit " + xyz + " --q-component 1 --field mpu -o " + D + "/other.mlf", d).code == 0);
    const auto r = sh("MESHLESS isosurface " + xyz + " --iso 0.6 --field " + D + "/other.mlf -o " + D + "/x.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("fitted to other data"));
    CHECK_FALSE(std::filesystem::exists(d.path / "x.ply"));
}

TEST_CASE("isosurface BLOCKS: the PLY carries the block of each point, points on the sphere", "[cli][multiblock]") {
    TempDir d("mbply");
    const std::string xyz = write_sphere_blocks(d);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS isosurface " + xyz + " --iso 0.6 --field rbf-grid -o " + D + "/a.ply", d).code == 0);
    const std::string bytes = slurp(d / "a.ply");
    CHECK_THAT(bytes, Catch::Contains("property float value\nproperty uint block\n"));
    CHECK_THAT(bytes, Catch::Contains("comment projection newton"));
    CHECK_THAT(bytes, Catch::Contains("comment field rbf-grid"));
    const PlyPoints p = read_ply_points((d / "a.ply").string());
    REQUIRE(p.block.size() == p.points.size());
    REQUIRE(p.points.size() > 1000);
    std::size_t per[2] = {0, 0};
    double worst = 0;
    for (std::size_t i = 0; i < p.points.size(); ++i) {
        REQUIRE(p.block[i] < 2);
        ++per[p.block[i]];
        const auto& q = p.points[i];
        worst = std::max(worst, std::abs(std::sqrt(double(q.pos[0]) * q.pos[0] + double(q.pos[1]) * q.pos[1] + double(q.pos[2]) * q.pos[2]) - 0.6));
        // block 0 covers x <= 0.25, block 1 x >= -0.25 (sheared by at most 0.3)
        if (p.block[i] == 0) CHECK(q.pos[0] < 0.25f + 0.1f);
        if (p.block[i] == 1) CHECK(q.pos[0] > -0.25f - 0.1f);
    }
    CHECK(per[0] > 100);
    CHECK(per[1] > 100);
    CHECK(worst < 0.02);  // the rbf-grid field of |p| sampled at h <= 0.2 reproduces the sphere closely
    // stdout (the points wait in an unlinked spool until the count is known): the same bytes, the
    // block ids and block colours included
    REQUIRE(sh("MESHLESS isosurface " + xyz + " --iso 0.6 --field rbf-grid --ply-color block -o " + D + "/c.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + xyz + " --iso 0.6 --field rbf-grid --ply-color block -o - | cat > " + D + "/c2.ply", d).code == 0);
    CHECK(slurp(d / "c.ply") == slurp(d / "c2.ply"));
    CHECK_THAT(slurp(d / "c.ply"), Catch::Contains("property uint block\nproperty uchar red"));
}

TEST_CASE("isosurface BLOCKS: an isovalue outside every block's range warns and writes empty valid outputs", "[cli][multiblock]") {
    TempDir d("mbrange");
    const std::string xyz = write_sphere_blocks(d);
    const std::string D = d.path.string();
    auto r = sh("MESHLESS isosurface " + xyz + " --iso 5 --field mpu -o " + D + "/e.ply --png " + D + "/e.png --size 64x64 --stats", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("outside the data range"));
    const std::string e = slurp(d / "e.ply");
    CHECK_THAT(e, Catch::Contains("element vertex 0"));
    CHECK_THAT(e, Catch::Contains("property uint block"));
    CHECK(read_ply_points((d / "e.ply").string()).points.empty());
    CHECK(fs::file_size(d / "e.png") > 0);
    r = sh("MESHLESS generate " + xyz + " --iso 5 | MESHLESS project --field mpu " + xyz + " | MESHLESS write -o " + D + "/f.ply", d);
    CHECK(r.code == 0);
    CHECK(slurp(d / "f.ply") == e);
}

TEST_CASE("isosurface BLOCKS: mistakes with seed streams and options are usage or data errors", "[cli][multiblock]") {
    TempDir d("mberr");
    const std::string xyz = write_sphere_blocks(d);
    const std::string D = d.path.string();
    auto r = sh("MESHLESS generate " + xyz + " --iso 0.6 | MESHLESS write -o " + D + "/x.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("unprojected seeds"));
    CHECK(!fs::exists(d / "x.ply"));
    r = sh("MESHLESS generate " + xyz + " --iso 0.6 | MESHLESS splat -o " + D + "/x.png", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("project them first"));
    r = sh("MESHLESS generate " + xyz + " --iso 0.6 | MESHLESS project", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--field"));
    r = sh("MESHLESS isosurface " + xyz + " --iso 0.6 --samples 0 -o " + D + "/x.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--samples"));
    r = sh("MESHLESS isosurface " + xyz + " --iso 0.6 --tolerance 0 -o " + D + "/x.ply", d);
    CHECK(r.code == 1);
    r = sh("MESHLESS isosurface " + xyz + " --iso 0.6 --projection exact -o " + D + "/x.ply", d);
    CHECK(r.code == 1);  // a volume option on blocks
    CHECK(!fs::exists(d / "x.ply"));
    r = sh("MESHLESS isosurface " + xyz + " --help", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("--samples"));
    r = sh("MESHLESS project --field mpu --help", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("--max-iterations"));
}

TEST_CASE("isosurface BLOCKS on the three combustor pieces: in-process equals pipes", "[cli][multiblock][real]") {
    if (!have_shared_data()) SUCCEED("no shared data");
    else {
        TempDir d("mbcomb");
        const std::string D = d.path.string();
        const std::string P = (shared_data() / "plot3d").string();
        const std::string blocks = P + "/multicomb_0.vts " + P + "/multicomb_1.vts " + P + "/multicomb_2.vts";
        auto r = sh("MESHLESS isosurface " + blocks + " --iso 0.4 --field mpu --threads 2 -o " + D + "/a.ply --stats", d);
        REQUIRE(r.code == 0);
        CHECK_THAT(r.err, Catch::Contains("3 blocks"));
        REQUIRE(sh("MESHLESS generate " + blocks + " --iso 0.4 | MESHLESS project --field mpu " + blocks + " --threads 1 | MESHLESS write -o " +
                       D + "/b.ply",
                   d).code == 0);
        CHECK(slurp(d / "a.ply") == slurp(d / "b.ply"));
        const PlyPoints p = read_ply_points((d / "a.ply").string());
        std::set<std::uint32_t> ids(p.block.begin(), p.block.end());
        CHECK(ids == std::set<std::uint32_t>{0, 1, 2});
    }
}

TEST_CASE("an option of another input kind points to the help of this input's variant", "[cli][multiblock]") {
    // `isosurface BLOCKS --projection exact` used to say "see meshless isosurface --help", whose
    // volume section lists --projection
    TempDir d("variant_help");
    const std::string vol = write_uint8_analytic_volume(d, "sphere", AnalyticField::sphere, 8, 100, 0);
    REQUIRE(sh("MESHLESS split " + vol + " --layout overlapping -o " + d.path.string() + "/b.vtm", d).code == 0);
    const std::string blocks = d.path.string() + "/b.vtm";
    const RunResult r = sh("MESHLESS isosurface " + blocks + " --iso 50 -o " + d.path.string() + "/x.ply --projection exact", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("unknown option '--projection' (the options for multiblock grids: meshless isosurface '" +
                                      blocks + "' --help)"));
}
