// meshless render (cli/cmd_render.cpp) as users run it: a volume, its brick store, scattered points
// through mpu; the same bytes for any --threads; --compare (PSNR inf of identical pictures) and
// --diff; bad sizes, bad transfer-function files and mismatched fields refused with nothing written.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

#include "cli/cli_harness.hpp"
#include "formats/png_reader.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

/// 4000 random points of exp(-4 |p|^2) over [-1, 1]^3 as CSV.
std::string write_blob_points(const TempDir& d) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-1, 1);
    std::ostringstream s;
    s << "x,y,z,v\n";
    for (int i = 0; i < 4000; ++i) {
        const double x = u(rng), y = u(rng), z = u(rng);
        s << x << "," << y << "," << z << "," << std::exp(-4 * (x * x + y * y + z * z)) << "\n";
    }
    const auto p = d / "blob.csv";
    spit(p, s.str());
    return p.string();
}

}  // namespace

TEST_CASE("render: a volume, the same bytes for any --threads, its brick store alike", "[cli][render]") {
    TempDir d("render");
    const std::string vol = write_uint8_analytic_volume(d, "sphere", AnalyticField::sphere, 40, 200, 20);
    const std::string D = d.path.string();
    const RunResult one = sh("MESHLESS render " + vol + " -o " + D + "/one.png --tf ct-skin --shade --size 96x80 --threads 1 --stats", d);
    INFO(one.err);
    REQUIRE(one.code == 0);
    CHECK(contains(one.err, "samples"));
    const RunResult two = sh("MESHLESS render " + vol + " -o " + D + "/two.png --tf ct-skin --shade --size 96x80 --threads 2", d);
    REQUIRE(two.code == 0);
    CHECK(slurp(D + "/one.png") == slurp(D + "/two.png"));
    const Image img = read_png(D + "/one.png");
    CHECK(img.width == 96);
    CHECK(img.height == 80);
    int lit = 0;
    for (std::uint8_t b : img.rgb) lit += b > 20;
    CHECK(lit > 500);
    // without empty-space skipping: the same picture (a volume's bounds are exact)
    REQUIRE(sh("MESHLESS render " + vol + " -o " + D + "/noskip.png --tf ct-skin --shade --size 96x80 --no-skip", d).code == 0);
    CHECK(slurp(D + "/one.png") == slurp(D + "/noskip.png"));
    // the brick store renders the same picture through the cache, within --memory
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/v.mlb --brick 8", d).code == 0);
    const RunResult st = sh("MESHLESS render " + D + "/v.mlb -o " + D + "/store.png --tf ct-skin --shade --size 96x80 --memory 64K", d);
    INFO(st.err);
    REQUIRE(st.code == 0);
    CHECK(slurp(D + "/one.png") == slurp(D + "/store.png"));
}

TEST_CASE("render --compare prints PSNR inf for identical pictures and writes the difference", "[cli][render]") {
    TempDir d("render");
    const std::string vol = write_uint8_analytic_volume(d, "torus", AnalyticField::torus, 32, 200, 20);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS render " + vol + " -o " + D + "/a.png --size 64x64", d).code == 0);
    const RunResult same = sh("MESHLESS render " + vol + " -o " + D + "/b.png --size 64x64 --compare " + D + "/a.png --diff " + D + "/d.png", d);
    INFO(same.err);
    REQUIRE(same.code == 0);
    CHECK(contains(same.out, "RMSE 0.0000 PSNR inf dB"));
    const Image diff = read_png(D + "/d.png");
    for (std::uint8_t b : diff.rgb) REQUIRE(b == 0);
    const RunResult other = sh("MESHLESS render " + vol + " -o " + D + "/c.png --size 64x64 --azimuth 60 --compare " + D + "/a.png --diff " + D + "/d2.png", d);
    REQUIRE(other.code == 0);
    CHECK(contains(other.out, "PSNR "));
    CHECK_FALSE(contains(other.out, "PSNR inf"));
    // sizes differ: exit 2 naming the reference, before rendering, with nothing written
    const RunResult wrong = sh("MESHLESS render " + vol + " -o " + D + "/e.png --size 32x32 --compare " + D + "/a.png --diff " + D + "/e2.png", d);
    CHECK(wrong.code == 2);
    CHECK(contains(wrong.err, D + "/a.png"));
    CHECK_FALSE(fs::exists(d / "e.png"));
    CHECK_FALSE(fs::exists(d / "e2.png"));
    CHECK(sh("MESHLESS render " + vol + " -o " + D + "/f.png --diff " + D + "/g.png", d).code == 1);
    CHECK(sh("MESHLESS render " + vol + " -o " + D + "/f.png --compare " + D + "/a.png --diff " + D + "/f.png", d).code == 1);
    // the picture on a pipe whose reader goes away: --diff is still written, quiet exit 0, and the
    // comparison goes to stderr (stdout holds the picture)
    const RunResult piped = sh("MESHLESS render " + vol + " -o - --size 64x64 --compare " + D + "/a.png --diff " + D + "/d3.png | true", d);
    CHECK(piped.code == 0);
    CHECK(contains(piped.err, "RMSE 0.0000 PSNR inf dB"));
    CHECK(slurp(d / "d3.png") == slurp(d / "d.png"));
    const RunResult piped_diff = sh("MESHLESS render " + vol + " -o " + D + "/b2.png --size 64x64 --compare " + D + "/a.png --diff - | true", d);
    CHECK(piped_diff.code == 0);
    CHECK(contains(piped_diff.err, "RMSE 0.0000 PSNR inf dB"));
    CHECK(slurp(d / "b2.png") == slurp(d / "a.png"));
}

TEST_CASE("render: scattered points through mpu, and the fields that do not fit the input refused", "[cli][render]") {
    TempDir d("render");
    const std::string pts = write_blob_points(d);
    const std::string D = d.path.string();
    const RunResult r = sh("MESHLESS render " + pts + " --field mpu -o " + D + "/p1.png --size 48x48 --tf viridis --threads 1 --stats", d);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(contains(r.err, "mpu field"));
    REQUIRE(sh("MESHLESS render " + pts + " --field mpu -o " + D + "/p2.png --size 48x48 --tf viridis --threads 2", d).code == 0);
    CHECK(slurp(D + "/p1.png") == slurp(D + "/p2.png"));
    // points without --field: mpu, as isosurface builds for them
    const RunResult dflt = sh("MESHLESS render " + pts + " -o " + D + "/p3.png --size 48x48 --tf viridis --threads 1 --stats", d);
    REQUIRE(dflt.code == 0);
    CHECK(contains(dflt.err, "mpu field"));
    CHECK(slurp(D + "/p3.png") == slurp(D + "/p1.png"));
    const RunResult help = sh("MESHLESS render --help", d);
    CHECK(contains(help.out, "mpu for point sets, rbf-grid for multiblock inputs"));
    if (have_shared_data()) {  // raw float32 x,y,z,v records are points here too, as isosurface and probe read them
        const std::string particles = (shared_data() / "scattered" / "Particles.raw").string();
        const RunResult raw = sh("MESHLESS render " + particles + " -o " + D + "/p4.png --size 48x48 --stats", d);
        INFO(raw.err);
        CHECK(raw.code == 0);
        CHECK(contains(raw.err, "197 points, mpu field"));
    }
    if (have_shared_data()) {  // multiblock grids without --field: rbf-grid, as isosurface builds for them
        const std::string P = (shared_data() / "plot3d").string();
        const std::string vts = P + "/multicomb_0.vts " + P + "/multicomb_1.vts " + P + "/multicomb_2.vts";
        const RunResult mb = sh("MESHLESS render " + vts + " -o " + D + "/mb.png --size 24x24 --threads 2 --stats", d);
        INFO(mb.err);
        CHECK(mb.code == 0);
        CHECK(contains(mb.err, "rbf-grid field"));
    }
    const RunResult tri = sh("MESHLESS render " + pts + " --field trilinear -o " + D + "/x.png", d);
    CHECK(tri.code == 1);
    CHECK(contains(tri.err, "not a volume"));
    const std::string vol = write_uint8_analytic_volume(d, "sphere", AnalyticField::sphere, 16, 200, 20);
    const RunResult mpu = sh("MESHLESS render " + vol + " --field mpu -o " + D + "/y.png", d);
    CHECK(mpu.code == 1);
    CHECK(contains(mpu.err, "is a volume"));
    CHECK_FALSE(std::filesystem::exists(D + "/x.png"));
    CHECK_FALSE(std::filesystem::exists(D + "/y.png"));
    // options that would change nothing are refused, naming what they are for (they were ignored:
    // exit 0, the same bytes)
    const std::string vol2 = write_uint8_analytic_volume(d, "torus", AnalyticField::torus, 16, 200, 20);
    const struct {
        std::string cmd, says;
    } refused[] = {
        {vol + " --hardy-c 0.1", "--hardy-c applies to point sets and multiblock grids; "},
        {vol + " --lod-level 3", "--lod-level applies to point sets"},
        {vol + " --columns 0,1,2,3", "is a volume, rendered through its trilinear interpolant"},
        {vol + " " + vol2, "is a volume: meshless render takes one volume"},  // (was mixed into one point set)
        {pts + " --binning 9", "--binning tunes the rbf-grid field; the field here is mpu"},
        {pts + " --field rbf-grid --alpha 0.8", "--alpha tunes the mpu field; the field here is rbf-grid"},
        {pts + " --lod-level 3", "--lod-level picks a level of detail of a cluster tree (.mlh)"},
        {pts + " --spacing 1,1,2", "--spacing applies to volumes"},
    };
    for (const auto& r : refused) {
        INFO(r.cmd);
        const RunResult x = sh("MESHLESS render " + r.cmd + " -o " + D + "/z.png --size 16x16", d);
        CHECK(x.code == 1);
        CHECK(contains(x.err, r.says));
        CHECK_FALSE(std::filesystem::exists(D + "/z.png"));
    }
    // still taken: --endian for a raw volume, and several .raw point files (float32 x,y,z,v records)
    CHECK(sh("MESHLESS render " + vol + " --endian little -o " + D + "/e.png --size 16x16", d).code == 0);
    if (have_shared_data()) {
        const std::string particles = (shared_data() / "scattered" / "Particles.raw").string();
        std::filesystem::copy_file(particles, D + "/p1.raw");
        std::filesystem::copy_file(particles, D + "/p2.raw");
        const RunResult two = sh("MESHLESS render " + D + "/p1.raw " + D + "/p2.raw -o " + D + "/pp.png --size 16x16", d);
        INFO(two.err);
        CHECK(two.code == 0);
    }
}

TEST_CASE("render refuses image sizes of 0 or beyond 16384 and bad transfer functions, writing nothing", "[cli][render]") {
    TempDir d("render");
    const std::string vol = write_uint8_analytic_volume(d, "sphere", AnalyticField::sphere, 16, 200, 20);
    const std::string D = d.path.string();
    for (const char* size : {"0x10", "10x0", "16385x10", "10x16385", "axb", "-1x5"}) {
        const RunResult r = sh("MESHLESS render " + vol + " -o " + D + "/s.png --size " + size, d);
        INFO(size << ": " << r.err);
        CHECK(r.code == 1);
        CHECK(contains(r.err, "--size"));
    }
    spit(d / "unsorted.tf", "0 0 0 0 0\n100 1 1 1 1\n50 1 1 1 1\n");
    spit(d / "range.tf", "0 0 0 0 0\n100 1 2 1 1\n");
    const RunResult u = sh("MESHLESS render " + vol + " -o " + D + "/s.png --tf " + D + "/unsorted.tf", d);
    CHECK(u.code == 2);
    CHECK(contains(u.err, D + "/unsorted.tf:3:"));
    const RunResult o = sh("MESHLESS render " + vol + " -o " + D + "/s.png --tf " + D + "/range.tf", d);
    CHECK(o.code == 2);
    CHECK(contains(o.err, D + "/range.tf:2:"));
    const RunResult missing = sh("MESHLESS render " + vol + " -o " + D + "/s.png --tf bone", d);
    CHECK(missing.code == 1);
    CHECK(contains(missing.err, "neither a preset"));
    CHECK(sh("MESHLESS render " + vol + " -o " + D + "/s.png --step 0", d).code == 1);
    CHECK(sh("MESHLESS render " + vol + " -o " + D + "/s.txt", d).code == 1);
    CHECK_FALSE(std::filesystem::exists(D + "/s.png"));
    // a good file works
    spit(d / "good.tf", "# value r g b a\n0 0 0 0 0\n120 1 0.5 0 0.3\n255 1 1 1 0.8\n");
    CHECK(sh("MESHLESS render " + vol + " -o " + D + "/s.png --size 32x32 --tf " + D + "/good.tf", d).code == 0);
}
