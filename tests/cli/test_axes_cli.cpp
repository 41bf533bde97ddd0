// --axes on the pictures of isosurface and splat: the triad and the scale bar drawn over the same
// splats (the picture differs from the plain one only at the bottom), the same from the points' file.
#include <catch2/catch.hpp>

#include "cli/cli_harness.hpp"
#include "formats/png_reader.hpp"

using namespace meshless;
using namespace meshless::test;

TEST_CASE("pictures with --axes: the triad and the scale bar at the bottom of isosurface and splat pictures", "[cli][axes]") {
    TempDir d("axes-cli");
    const std::string D = d.path.string();
    const std::string vol = write_uint8_analytic_volume(d, "ball", AnalyticField::sphere, 32, 200, 20);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "/b.ply --png " + D + "/plain.png --size 160x160", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 --png " + D + "/axes.png --size 160x160 --axes", d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "/b.ply -o " + D + "/splat.png --size 160x160 --axes", d).code == 0);
    CHECK(slurp(d / "splat.png") == slurp(d / "axes.png"));
    const Image plain = read_png((d / "plain.png").string()), axes = read_png((d / "axes.png").string());
    REQUIRE(plain.width == 160);
    REQUIRE(axes.width == 160);
    int top = 0, bottom = 0;
    for (int y = 0; y < 160; ++y)
        for (int x = 0; x < 160; ++x)
            if (plain.at(x, y) != axes.at(x, y)) (y < 112 ? top : bottom) += 1;
    CHECK(top == 0);      // the splats untouched
    CHECK(bottom > 40);   // the triad, the bar and its label
    CHECK(sh("MESHLESS isosurface --help", d).out.find("--axes") != std::string::npos);
}

TEST_CASE("render --colorbar --axes: the transfer function's legend and the axes over the same rendering", "[cli][axes]") {
    TempDir d("axes-render");
    const std::string D = d.path.string();
    const std::string vol = write_uint8_analytic_volume(d, "ball", AnalyticField::sphere, 32, 200, 20);
    REQUIRE(sh("MESHLESS render " + vol + " --size 160x160 -o " + D + "/plain.png", d).code == 0);
    REQUIRE(sh("MESHLESS render " + vol + " --size 160x160 -o " + D + "/deco.png --colorbar --axes --tf viridis", d).code == 0);
    REQUIRE(sh("MESHLESS render " + vol + " --size 160x160 -o " + D + "/vir.png --tf viridis", d).code == 0);
    const Image vir = read_png((d / "vir.png").string()), deco = read_png((d / "deco.png").string());
    int legend = 0, bottom = 0, middle = 0;
    for (int y = 0; y < 160; ++y)
        for (int x = 0; x < 160; ++x) {
            if (vir.at(x, y) == deco.at(x, y)) continue;
            if (x >= 140) ++legend;          // the bar at the right edge
            else if (y >= 112) ++bottom;     // the triad and the scale bar
            else ++middle;
        }
    CHECK(legend > 100);
    CHECK(bottom > 40);
    CHECK(middle < 60);  // the legend's title and top value reach left of the bar; the rendering is untouched
    const auto cmp = sh("MESHLESS render " + vol + " --size 160x160 -o " + D + "/again.png --tf viridis --compare " + D + "/vir.png", d);
    CHECK(cmp.code == 0);
    CHECK(cmp.out.find("PSNR inf") != std::string::npos);
}
