// `meshless splat` / `isosurface --png` colours from the command line: --color modes give different
// pictures and the same bytes for any --threads; the default leaves an isosurface uncoloured (the
// picture of --color none) and colours a scattered PLY with varying values by value; --colorbar
// draws the legend where kernels/colorbar.hpp lays it out; --color block without block ids is a
// usage error naming the input.
#include <catch2/catch.hpp>

#include <string>

#include "cli/cli_harness.hpp"
#include "formats/ply_points.hpp"
#include "formats/png_writer.hpp"
#include "kernels/colorbar.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

/// A 40^3 uint8 ball (radius 12 voxels) written as NAME_40x40x40_uint8.raw.
std::string ball(const TempDir& d) {
    const int n = 40;
    std::string bytes(static_cast<std::size_t>(n) * n * n, '\0');
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double r = std::sqrt((i - 20.0) * (i - 20.0) + (j - 19.0) * (j - 19.0) + (k - 21.0) * (k - 21.0));
                bytes[static_cast<std::size_t>(i + n * (j + n * k))] = static_cast<char>(static_cast<unsigned char>(std::clamp(220.0 - 10.0 * r, 0.0, 255.0)));
            }
    const std::string path = (d / "ball_40x40x40_uint8.raw").string();
    spit(path, bytes);
    return path;
}

}  // namespace

TEST_CASE("splat --color: modes differ, bytes do not depend on --threads, the default follows the input", "[cli][splat][color]") {
    TempDir d("splatcolor");
    const std::string vol = ball(d), D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "iso.ply", d).code == 0);
    // the same points without the isovalue comment and with values varying along x
    PlyPoints pts = read_ply_points(D + "iso.ply");
    REQUIRE(pts.points.size() > 100);
    for (auto& p : pts.points) p.value = p.pos[0];
    write_ply_points(D + "scattered.ply", pts.points, {});
    const std::string opt = " --size 96x80 --kernel ";
    for (const char* k : {"quad", "ewa"}) {
        INFO(k);
        for (const char* mode : {"value", "normal", "none"}) {
            for (const char* t : {"1", "3"})
                REQUIRE(sh("MESHLESS splat " + D + "scattered.ply" + opt + k + " --color " + mode + " --threads " + t + " -o " + D + mode +
                               t + ".png",
                           d).code == 0);
            CHECK(slurp(d / (std::string(mode) + "1.png")) == slurp(d / (std::string(mode) + "3.png")));
        }
        CHECK(slurp(d / "value1.png") != slurp(d / "normal1.png"));
        CHECK(slurp(d / "value1.png") != slurp(d / "none1.png"));
        CHECK(slurp(d / "normal1.png") != slurp(d / "none1.png"));
        // default: a scattered set with varying values is coloured by value; an isosurface is not
        REQUIRE(sh("MESHLESS splat " + D + "scattered.ply" + opt + k + " -o " + D + "auto.png", d).code == 0);
        CHECK(slurp(d / "auto.png") == slurp(d / "value1.png"));
        REQUIRE(sh("MESHLESS splat " + D + "iso.ply" + opt + k + " -o " + D + "iso_auto.png", d).code == 0);
        REQUIRE(sh("MESHLESS splat " + D + "iso.ply" + opt + k + " --color none -o " + D + "iso_none.png", d).code == 0);
        CHECK(slurp(d / "iso_auto.png") == slurp(d / "iso_none.png"));
        // in-process isosurface: the same default picture as splatting its PLY
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5" + opt + k + " --png " + D + "inproc.png", d).code == 0);
        CHECK(slurp(d / "inproc.png") == slurp(d / "iso_none.png"));
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5" + opt + k + " --color normal --png " + D + "inproc_n.png", d).code == 0);
        CHECK(slurp(d / "inproc_n.png") != slurp(d / "inproc.png"));
    }
}

TEST_CASE("splat --colorbar: the legend's pixels are the colour map's, labels drawn", "[cli][splat][color]") {
    TempDir d("splatbar");
    const std::string vol = ball(d), D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "iso.ply", d).code == 0);
    PlyPoints pts = read_ply_points(D + "iso.ply");
    for (auto& p : pts.points) p.value = p.pos[1];
    write_ply_points(D + "s.ply", pts.points, {});
    REQUIRE(sh("MESHLESS splat " + D + "s.ply --size 320x240 --color value --range -4,12 --colorbar -o " + D + "bar.png", d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "s.ply --size 320x240 --color value --range -4,12 -o " + D + "plain.png", d).code == 0);
    const Image bar = read_png(D + "bar.png"), plain = read_png(D + "plain.png");
    const ColorbarLayout l = colorbar_layout(320, 240);
    REQUIRE(l.drawn);
    const int n = l.y1 - l.y0;
    for (int y : {l.y0, (l.y0 + l.y1) / 2, l.y1 - 1}) {
        INFO("row " << y);
        CHECK(bar.at((l.x0 + l.x1) / 2, y) == map_color(Colormap::viridis, 12 - (y - l.y0 + 0.5) / n * 16, -4, 12));
    }
    CHECK(bar.at(l.x0 - 1, l.y0 + 3) == std::array<std::uint8_t, 3>{255, 255, 255});
    int changed = 0;
    for (int y = 0; y < 240; ++y)
        for (int x = 0; x < 320; ++x) changed += bar.at(x, y) != plain.at(x, y);
    CHECK(changed > (l.x1 - l.x0) * n);  // bar + frame + labels
    // isosurface --png --colorbar with --color value: the volume's range by default
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 --size 320x240 --color value --colorbar --png " + D + "iso_bar.png", d).code == 0);
    const Image ib = read_png(D + "iso_bar.png");
    CHECK(ib.at((l.x0 + l.x1) / 2, l.y1 - 1) == map_color(Colormap::viridis, 220 - (n - 0.5) / n * 220, 0, 220));
    // a colour bar without value colours: a warning, no bar
    const auto w = sh("MESHLESS splat " + D + "s.ply --size 320x240 --color normal --colorbar -o " + D + "nb.png", d);
    CHECK(w.code == 0);
    CHECK(w.err.find("--colorbar") != std::string::npos);
}

TEST_CASE("splat --color block without block ids, bad --color / --range: usage errors naming the input", "[cli][splat][color]") {
    TempDir d("splatblock");
    const std::string vol = ball(d), D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "iso.ply", d).code == 0);
    auto r = sh("MESHLESS splat " + D + "iso.ply --color block -o " + D + "b.png", d);
    CHECK(r.code == 1);
    CHECK(r.err.find("iso.ply") != std::string::npos);
    CHECK(r.err.find("block") != std::string::npos);
    r = sh("MESHLESS splat --color block -o " + D + "b.png < " + D + "iso.ply", d);  // not a stream: a format error
    CHECK(r.code != 0);
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 100.5 | MESHLESS project > " + D + "pts.mls", d).code == 0);
    r = sh("MESHLESS splat " + D + "pts.mls --color block -o " + D + "b.png", d);
    CHECK(r.code == 1);
    CHECK(r.err.find("pts.mls") != std::string::npos);
    r = sh("MESHLESS isosurface " + vol + " --iso 100.5 --color block --png " + D + "b.png", d);
    CHECK(r.code == 1);
    CHECK(r.err.find("ball_40x40x40_uint8.raw") != std::string::npos);
    CHECK(sh("MESHLESS splat " + D + "iso.ply --color rainbow -o " + D + "b.png", d).code == 1);
    CHECK(sh("MESHLESS splat " + D + "iso.ply --color value --range 3,1 -o " + D + "b.png", d).code == 1);
    CHECK(sh("MESHLESS splat " + D + "iso.ply --color value --colormap jet -o " + D + "b.png", d).code == 1);
    CHECK_FALSE(std::filesystem::exists(d / "b.png"));
}

TEST_CASE("splat of an isosurface's PLY colours by value and lists blocks as isosurface --png does", "[cli][splat][color]") {
    TempDir d("splat_color_recorded");
    const std::string vol = ball(d), D = d.path.string() + "/";
    // --color value: the points all hold the isovalue; both pictures map it within the volume's
    // range, which the PLY records (value_min/value_max), instead of a range of one value
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "i.ply --png " + D + "i.png --size 64x64 --color value "
               "--colorbar",
               d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "i.ply -o " + D + "s.png --size 64x64 --color value --colorbar", d).code == 0);
    const std::string ply = slurp(d / "i.ply");
    CHECK(ply.find("comment value_min 0\n") != std::string::npos);
    CHECK(ply.find("comment value_max ") != std::string::npos);
    CHECK(slurp(d / "i.png") == slurp(d / "s.png"));
    // the same through a pipe: the stream's metadata records the range too
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 100.5 | MESHLESS project | MESHLESS splat -o " + D +
                   "p.png --size 64x64 --color value --colorbar",
               d).code == 0);
    CHECK(slurp(d / "i.png") == slurp(d / "p.png"));
    if (!have_shared_data()) return;
    // --color block --colorbar: as many swatches as the PLY's recorded blocks (3), not the palette's 10
    const std::string P = (shared_data() / "plot3d").string() + "/";
    const std::string blocks = P + "multicomb_0.vts " + P + "multicomb_1.vts " + P + "multicomb_2.vts";
    REQUIRE(sh("MESHLESS isosurface " + blocks + " --iso 0.4 -o " + D + "b.ply --png " + D + "b.png --size 200x200 --color block "
               "--colorbar",
               d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "b.ply -o " + D + "bs.png --size 200x200 --color block --colorbar", d).code == 0);
    CHECK(slurp(d / "b.png") == slurp(d / "bs.png"));
}
