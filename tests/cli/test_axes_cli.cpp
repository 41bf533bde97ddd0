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

namespace {
/// The ball volume as an NRRD (detached raw data beside it) whose header says `units` (none when empty).
std::string ball_nrrd(const TempDir& d, const std::string& raw, const std::string& name, const std::string& units) {
    const std::string path = (d.path / name).string();
    spit(path, "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 32 32 32\nencoding: raw\nspacings: 1 1 1\n" + units +
                   "data file: " + std::filesystem::path(raw).filename().string() + "\n\n");
    return path;
}
/// Pixels that differ between two pictures of one size, counted above and below y = split.
std::array<int, 2> differing(const Image& a, const Image& b, int split) {
    std::array<int, 2> n{0, 0};
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (a.at(x, y) != b.at(x, y)) ++n[y < split ? 0 : 1];
    return n;
}
}  // namespace

TEST_CASE("the axes are drawn by default where the volume's file states its length unit, labelled with it", "[cli][axes]") {
    TempDir d("axes-units");
    const std::string D = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "ball", AnalyticField::sphere, 32, 200, 20);
    const std::string mm = ball_nrrd(d, vol, "mm.nhdr", "space units: \"mm\" \"mm\" \"mm\"\n");
    const std::string none = ball_nrrd(d, vol, "none.nhdr", "");
    const std::string mixed = ball_nrrd(d, vol, "mixed.nhdr", "space units: \"mm\" \"mm\" \"um\"\n");
    CHECK_THAT(sh("MESHLESS info " + mm, d).out, Catch::Contains("length unit: mm"));
    CHECK_THAT(sh("MESHLESS info " + mixed, d).out, !Catch::Contains("length unit"));
    const auto pic = [&](const std::string& in, const std::string& out, const std::string& more) {
        const RunResult r = sh("MESHLESS isosurface " + in + " --iso 100.5 --png " + D + out + " --size 160x160 " + more, d);
        INFO(r.err);
        REQUIRE(r.code == 0);
        return read_png(D + out);
    };
    const Image def = pic(mm, "mm.png", ""), on = pic(mm, "mm_on.png", "--axes"), off = pic(mm, "mm_off.png", "--no-axes");
    const Image plain = pic(none, "none.png", ""), plain_on = pic(none, "none_on.png", "--axes");
    CHECK(slurp(d / "mm.png") == slurp(d / "mm_on.png"));       // a known unit: drawn by default
    CHECK(slurp(d / "none.png") == slurp(d / "mm_off.png"));    // --no-axes, or no unit: nothing drawn
    (void)pic(mixed, "mixed.png", "");
    CHECK(slurp(d / "mixed.png") == slurp(d / "none.png"));    // units that disagree: not known
    const auto n = differing(off, def, 112);
    CHECK(n[0] == 0);
    CHECK(n[1] > 40);
    // the label "N mm" is wider than the bare "N" of a volume without units
    CHECK(differing(plain, def, 112)[1] > differing(plain, plain_on, 112)[1]);
    // the points record the unit: splat of their PLY draws the same picture, and so does a brick store
    REQUIRE(sh("MESHLESS isosurface " + mm + " --iso 100.5 -o " + D + "mm.ply", d).code == 0);
    CHECK_THAT(slurp(d / "mm.ply"), Catch::Contains("comment length_unit mm\n"));
    REQUIRE(sh("MESHLESS splat " + D + "mm.ply -o " + D + "mm_splat.png --size 160x160", d).code == 0);
    CHECK(slurp(d / "mm_splat.png") == slurp(d / "mm.png"));
    REQUIRE(sh("MESHLESS convert " + mm + " -o " + D + "mm.mlb --brick 8", d).code == 0);
    CHECK_THAT(sh("MESHLESS info " + D + "mm.mlb", d).out, Catch::Contains("length unit: mm"));
    (void)pic(D + "mm.mlb", "mlb.png", "");  // (a store frames the surface by its bricks: another picture)
    (void)pic(D + "mm.mlb", "mlb_on.png", "--axes");
    (void)pic(D + "mm.mlb", "mlb_off.png", "--no-axes");
    CHECK(slurp(d / "mlb.png") == slurp(d / "mlb_on.png"));
    CHECK(slurp(d / "mlb.png") != slurp(d / "mlb_off.png"));
    // render: the same default
    const auto render = [&](const std::string& in, const std::string& out, const std::string& more) {
        REQUIRE(sh("MESHLESS render " + in + " --size 160x160 -o " + D + out + " " + more, d).code == 0);
        return read_png(D + out);
    };
    const Image r_def = render(mm, "r_mm.png", ""), r_off = render(mm, "r_off.png", "--no-axes"), r_none = render(none, "r_none.png", "");
    CHECK(differing(r_off, r_def, 112)[1] > 40);
    CHECK(slurp(d / "r_off.png") == slurp(d / "r_none.png"));
    const RunResult both = sh("MESHLESS isosurface " + mm + " --iso 100.5 --png " + D + "x.png --axes --no-axes", d);
    CHECK(both.code == 1);
    CHECK_THAT(both.err, Catch::Contains("--axes and --no-axes: give one"));
}
