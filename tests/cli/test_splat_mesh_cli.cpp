// `meshless splat MESH.ply` draws a marching-cubes mesh as its triangles
// (kernels/triangle_rasterizer.hpp): the lit area matches the splatted isosurface of the same
// volume, the bytes do not depend on --threads or --kernel, bad faces and impossible colours are
// refused naming the file.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "cli/cli_harness.hpp"
#include "formats/png_reader.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

/// A 33^3 uint8 ball, value 255 - 8 r about the centre (16, 16, 16): iso 128.5 is the sphere of
/// radius 15.8, which nearly fills the volume (the isosurface's framing box, one 32-voxel block),
/// so the mesh's bounds and the recorded surface bounds frame the same picture.
std::string full_ball(const TempDir& d) {
    const int n = 33;
    std::string bytes(static_cast<std::size_t>(n) * n * n, '\0');
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double r = std::sqrt((i - 16.0) * (i - 16.0) + (j - 16.0) * (j - 16.0) + (k - 16.0) * (k - 16.0));
                bytes[static_cast<std::size_t>(i + n * (j + n * k))] =
                    static_cast<char>(std::clamp(std::lround(255.0 - 8.0 * r), 0L, 255L));
            }
    const std::string path = (d / "ball_33x33x33_uint8.raw").string();
    spit(path, bytes);
    return path;
}

bool lit(const Image& img, int x, int y) {
    const auto c = img.at(x, y);
    return c[0] || c[1] || c[2];
}

}  // namespace

TEST_CASE("splat MESH.ply: the triangles cover what the splatted isosurface covers, same bytes for any --threads",
          "[cli][splat][mesh]") {
    TempDir d("splatmesh");
    const std::string vol = full_ball(d), D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS mc " + vol + " --iso 128.5 -o " + D + "mesh.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 128.5 --png " + D + "iso.png --size 256x224", d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "mesh.ply -o " + D + "m1.png --size 256x224 --threads 1", d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "mesh.ply -o " + D + "m2.png --size 256x224 --threads 2 --kernel quad", d).code == 0);
    CHECK(slurp(D + "m1.png") == slurp(D + "m2.png"));
    const Image iso = read_png(D + "iso.png"), mesh = read_png(D + "m1.png");
    REQUIRE(mesh.width == 256);
    REQUIRE(mesh.height == 224);
    std::int64_t both = 0, either = 0;
    for (int y = 0; y < 224; ++y)
        for (int x = 0; x < 256; ++x) {
            both += lit(iso, x, y) && lit(mesh, x, y);
            either += lit(iso, x, y) || lit(mesh, x, y);
        }
    INFO("IoU " << double(both) / double(either));
    CHECK(either > 3000);
    CHECK(double(both) / double(either) >= 0.9);

    // colours: normal differs from none; value needs values, block needs block ids (usage errors)
    REQUIRE(sh("MESHLESS splat " + D + "mesh.ply -o " + D + "n.png --size 256x224 --color normal", d).code == 0);
    CHECK(slurp(D + "n.png") != slurp(D + "m1.png"));
    for (const char* c : {"value", "block"}) {
        INFO(c);
        const RunResult r = sh("MESHLESS splat " + D + "mesh.ply -o " + D + "c.png --color " + std::string(c), d);
        CHECK(r.code == 1);
        CHECK(r.err.find("mesh.ply") != std::string::npos);
        CHECK_FALSE(fs::exists(D + "c.png"));
    }
    // a turntable writes its frames
    REQUIRE(sh("MESHLESS splat " + D + "mesh.ply -o " + D + "t.png --size 32x32 --turntable 3", d).code == 0);
    CHECK(fs::exists(D + "t_000.png"));
    CHECK(fs::exists(D + "t_002.png"));
    CHECK(slurp(D + "t_000.png") != slurp(D + "t_001.png"));
}

TEST_CASE("splat MESH.ply: a face index out of range is a data error naming the file", "[cli][splat][mesh]") {
    TempDir d("splatmeshbad");
    const std::string D = d.path.string() + "/";
    spit(D + "bad.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    const RunResult r = sh("MESHLESS splat " + D + "bad.ply -o " + D + "bad.png", d);
    CHECK(r.code == 2);
    CHECK(r.err.find("bad.ply") != std::string::npos);
    CHECK_FALSE(fs::exists(D + "bad.png"));
    // the same triangle with valid indices is drawn
    spit(D + "ok.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    REQUIRE(sh("MESHLESS splat " + D + "ok.ply -o " + D + "ok.png --size 64x64 --view +z", d).code == 0);
    const Image ok = read_png(D + "ok.png");
    std::int64_t n = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) n += lit(ok, x, y);
    CHECK(n > 200);
}
