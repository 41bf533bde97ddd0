// probe, slice and resample from the command line, against a linear field (which every meshless
// field reproduces) sampled at scattered points.
#include <catch2/catch.hpp>

#include <random>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

#include "cli/cli_harness.hpp"
#include "formats/png_writer.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/colorbar.hpp"
#include "kernels/colormap.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

double linear(double x, double y, double z) { return 2 * x - y + 0.5 * z + 3; }

/// 600 scattered points of the linear field, as CSV with a header.
std::string write_points(const TempDir& d) {
    std::ostringstream s;
    s << "x,y,z,value\n";
    unsigned r = 12345;
    auto u = [&] { r = r * 1103515245u + 12345u; return (r >> 8) / double(1 << 24); };
    for (int i = 0; i < 600; ++i) {
        const double x = u() * 10, y = u() * 4 + 100, z = u() * 6;
        s << x << "," << y << "," << z << "," << linear(x, y, z) << "\n";
    }
    const auto p = d / "pts.csv";
    spit(p, s.str());
    return p.string();
}

}  // namespace

TEST_CASE("probe reproduces a linear field and its gradient with every field kind", "[cli][fields]") {
    TempDir d("probe");
    const std::string pts = write_points(d), D = d.path.string();
    for (const char* f : {"rbf-grid", "mpu", "global-rbf"}) {
        INFO(f);
        const auto r = sh("MESHLESS probe " + pts + " --field " + std::string(f) + " --at 5,102,3 --at 2.5,101,1.5 -o " + D + "/p.csv", d);
        REQUIRE(r.code == 0);
        std::istringstream in(slurp(d / "p.csv"));
        std::string line;
        std::getline(in, line);
        CHECK(line == "x,y,z,value,gx,gy,gz");
        int rows = 0;
        while (std::getline(in, line)) {
            double v[7];
            REQUIRE(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6]) == 7);
            CHECK(v[3] == Approx(linear(v[0], v[1], v[2])).epsilon(1e-5));
            CHECK(v[4] == Approx(2).margin(1e-3));
            CHECK(v[5] == Approx(-1).margin(1e-3));
            CHECK(v[6] == Approx(0.5).margin(1e-3));
            ++rows;
        }
        CHECK(rows == 2);
    }
    CHECK(sh("MESHLESS probe " + pts + " --at 1,2", d).code == 1);
    CHECK(sh("MESHLESS probe " + pts, d).code == 1);
    spit(d / "three.csv", "x,y,z,value\n0,0,0,1\n1,0,0,2\n0,1,0,3\n");
    CHECK(sh("MESHLESS probe " + D + "/three.csv --at 0,0,0", d).code == 2);
}

TEST_CASE("resample writes a NRRD the volume commands read, with the field's values", "[cli][fields]") {
    TempDir d("resample");
    const std::string pts = write_points(d), D = d.path.string();
    REQUIRE(sh("MESHLESS resample " + pts + " --grid 11,5,7 --field mpu -o " + D + "/v.nrrd --threads 2", d).code == 0);
    const Volume v = read_volume(D + "/v.nrrd");
    REQUIRE(v.grid.dims == std::array<std::int64_t, 3>{11, 5, 7});
    const float* f = reinterpret_cast<const float*>(v.bytes.data());
    // interior samples (away from the hull's corners) reproduce the linear field
    const GridSpec& g = v.grid;
    for (std::int64_t k = 2; k < 5; ++k)
        for (std::int64_t j = 1; j < 4; ++j)
            for (std::int64_t i = 2; i < 9; ++i)
                CHECK(f[g.index(i, j, k)] == Approx(linear(g.origin[0] + i * g.spacing[0], g.origin[1] + j * g.spacing[1],
                                                           g.origin[2] + k * g.spacing[2]))
                                                 .epsilon(1e-4));
    CHECK(sh("MESHLESS isosurface " + D + "/v.nrrd --iso 0.5 -o " + D + "/i.ply", d).code == 0);
    CHECK(sh("MESHLESS resample " + pts + " --grid 1,5,7 -o " + D + "/x.nrrd", d).code == 1);
}

TEST_CASE("slice renders the plane with the bounding box's aspect", "[cli][fields]") {
    TempDir d("slice");
    const std::string pts = write_points(d), D = d.path.string();
    REQUIRE(sh("MESHLESS slice " + pts + " --plane y=102 --size 300x300 -o " + D + "/s.png --stats", d).code == 0);
    const Image img = read_png(D + "/s.png");
    CHECK(img.width == 300);  // x extent 10 vs z extent 6: the width is the long side
    CHECK(std::abs(img.height - 180) <= 2);
    CHECK(sh("MESHLESS slice " + pts + " --plane w=1 -o " + D + "/x.png", d).code == 1);
    // --quiet is accepted; stderr is not a terminal here, so nothing is drawn either way
    const auto q = sh("MESHLESS slice " + pts + " --plane y=102 --size 64x64 --quiet -o " + D + "/q.png", d);
    CHECK(q.code == 0);
    CHECK(q.err.empty());
    CHECK(sh("MESHLESS slice " + pts + " --plane z=1 -o " + D + "/x.png --colormap jet", d).code == 1);
}

TEST_CASE("slice --colorbar: the legend shows the colour map over --range", "[cli][fields]") {
    TempDir d("slicebar");
    const std::string pts = write_points(d), D = d.path.string();
    REQUIRE(sh("MESHLESS slice " + pts + " --plane y=102 --size 300x300 --range 0,30 --colormap viridis --colorbar -o " + D + "/b.png", d).code == 0);
    REQUIRE(sh("MESHLESS slice " + pts + " --plane y=102 --size 300x300 --range 0,30 --colormap viridis -o " + D + "/p.png", d).code == 0);
    const Image bar = read_png(D + "/b.png"), plain = read_png(D + "/p.png");
    const ColorbarLayout l = colorbar_layout(bar.width, bar.height);
    REQUIRE(l.drawn);
    const int n = l.y1 - l.y0;
    for (int y : {l.y0, (l.y0 + l.y1) / 2, l.y1 - 1}) {
        INFO("row " << y);
        CHECK(bar.at((l.x0 + l.x1) / 2, y) == map_color(Colormap::viridis, 30 - (y - l.y0 + 0.5) / n * 30, 0, 30));
        CHECK(plain.at((l.x0 + l.x1) / 2, y) != bar.at((l.x0 + l.x1) / 2, y));
    }
}

TEST_CASE("positions the data does not reach are NaN, unless --max-gap 0", "[cli][fields]") {
    TempDir d("gap");
    const std::string pts = write_points(d), D = d.path.string();
    REQUIRE(sh("MESHLESS probe " + pts + " --at 5,102,3 --at 40,102,3 -o " + D + "/p.csv", d).code == 0);
    const std::string out = slurp(d / "p.csv");
    CHECK(out.find("40,102,3,nan") != std::string::npos);
    CHECK(out.find("5,102,3,nan") == std::string::npos);
    // global-rbf is defined everywhere: without the coverage mask it extrapolates
    REQUIRE(sh("MESHLESS probe " + pts + " --field global-rbf --at 40,102,3 --max-gap 0 -o " + D + "/q.csv", d).code == 0);
    CHECK(slurp(d / "q.csv").find("nan") == std::string::npos);
    CHECK(sh("MESHLESS probe " + pts + " --at 1,1,1 --max-gap -1", d).code == 1);
}

TEST_CASE("extrapolate: NaN, the field kept within the data range, or the nearest value, --stats counts", "[cli][fields]") {
    TempDir d("extrapolate");
    const std::string pts = write_points(d), D = d.path.string();
    // data values: 2x - y + z/2 + 3 over x 0..10, y 100..104, z 0..6 -> about -101 .. -74
    const std::string far = " --at 5,102,3 --at 60,102,3";
    auto probe = [&](const std::string& opt) {
        const auto r = sh("MESHLESS probe " + pts + far + opt + " --stats -o " + D + "/p.csv", d);
        REQUIRE(r.code == 0);
        std::istringstream in(slurp(d / "p.csv"));
        std::string header, a, b;
        std::getline(in, header);
        std::getline(in, a);
        std::getline(in, b);
        return std::make_tuple(a, b, r.err);
    };
    const auto [a0, b0, e0] = probe("");
    CHECK(b0.find(",nan") != std::string::npos);
    CHECK_THAT(e0, Catch::Contains("1 positions outside the data (NaN)"));
    const auto [a1, b1, e1] = probe(" --extrapolate clamp");
    CHECK(a1 == a0);
    CHECK(b1.find("nan") == std::string::npos);
    const double v1 = std::stod(b1.substr(b1.find(',', b1.find(',', b1.find(',') + 1) + 1) + 1));
    CHECK(v1 <= -74.0);  // the linear field extrapolates to 2*60 - 102 + 1.5 + 3 = 22.5: kept within the data
    CHECK_THAT(e1, Catch::Contains("(clamped)"));
    const auto [a2, b2, e2] = probe(" --extrapolate nearest");
    const double v2 = std::stod(b2.substr(b2.find(',', b2.find(',', b2.find(',') + 1) + 1) + 1));
    CHECK(v2 > -80.0);  // the nearest data point has x close to 10
    CHECK(v2 <= -74.0);
    CHECK(sh("MESHLESS probe " + pts + " --at 1,101,1 --extrapolate zero", d).code == 1);
    // --at-file - reads the positions from standard input
    REQUIRE(sh("printf \"x,y,z\\n5,102,3\\n\" | MESHLESS probe " + pts + " --at-file - -o " + D + "/stdin.csv", d).code == 0);
    REQUIRE(sh("MESHLESS probe " + pts + " --at 5,102,3 -o " + D + "/arg.csv", d).code == 0);
    CHECK(slurp(d / "stdin.csv") == slurp(d / "arg.csv"));
    CHECK(sh("MESHLESS probe " + pts + " --at 1,101,1 --max-gap 0 --extrapolate clamp", d).code == 1);
    // a positions file without positions, or with a short first line, names the file (and line)
    spit(d / "empty.txt", "");
    spit(d / "short.txt", "5 102\n5 102 3\n");
    spit(d / "commented.txt", "# probe points\n\nx y z\n5 102 3\n");
    REQUIRE(sh("MESHLESS probe " + pts + " --at-file " + D + "/commented.txt -o " + D + "/c.csv", d).code == 0);
    CHECK(slurp(d / "c.csv") == slurp(d / "arg.csv"));
    const auto e = sh("MESHLESS probe " + pts + " --at-file " + D + "/empty.txt", d);
    CHECK(e.code == 2);
    CHECK_THAT(e.err, Catch::Contains("empty.txt: no positions"));
    const auto s = sh("MESHLESS probe " + pts + " --at-file " + D + "/short.txt", d);
    CHECK(s.code == 2);
    CHECK_THAT(s.err, Catch::Contains("short.txt:1: expected x,y,z"));
}

TEST_CASE("a field that overshoots its data warns that its values were clamped, smooth data does not", "[cli][fields]") {
    // newcomer trial 2: a quarter of a slice of the boreholes clamped, shown as flat colour, and
    // said only under --stats. Values 0 or 100 at random on a jittered grid make every field
    // overshoot between neighbours.
    TempDir d("fields-overshoot");
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    std::string csv = "x,y,z,v\n";
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (int k = 0; k < 8; ++k)
                csv += std::to_string(i + jitter(rng)) + "," + std::to_string(j + jitter(rng)) + "," + std::to_string(k + jitter(rng)) +
                       "," + (rng() % 2 ? "100" : "0") + "\n";
    spit(d / "noisy.csv", csv);
    const auto noisy = sh("MESHLESS slice " + (d / "noisy.csv").string() + " --plane z=3.5 --size 200x200 -o " + (d / "n.png").string(), d);
    CHECK(noisy.code == 0);
    CHECK_THAT(noisy.err, Catch::Contains("meshless slice: warning: ") && Catch::Contains("values inside the data") &&
                              Catch::Contains("were clamped to it"));
    const std::string pts = write_points(d);
    const auto smooth = sh("MESHLESS slice " + pts + " --plane z=0.5 --size 200x200 -o " + (d / "s.png").string(), d);
    CHECK(smooth.code == 0);
    CHECK(smooth.err.find("clamped") == std::string::npos);
    // --extrapolate clamp clamps the values outside the data on purpose: they are not counted (review:
    // a plane near the edge of a ball of points, v = r^2, warned "325 %")
    std::mt19937 brng(9);
    std::uniform_real_distribution<double> cube(-10, 10);
    std::string ball = "x,y,z,v\n";
    for (int n = 0; n < 4000;) {
        const double x = cube(brng), y = cube(brng), z = cube(brng), r2 = x * x + y * y + z * z;
        if (r2 > 100) continue;
        ball += std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(z) + "," + std::to_string(r2) + "\n";
        ++n;
    }
    spit(d / "ball.csv", ball);
    const auto edge = sh("MESHLESS slice " + (d / "ball.csv").string() + " --plane z=9.3 --size 200x200 --extrapolate clamp -o " +
                             (d / "b.png").string(), d);
    CHECK(edge.code == 0);
    CHECK(edge.err.find("clamped") == std::string::npos);
}

TEST_CASE("probe, slice and resample run as graphs: the same bytes for any --threads", "[cli][fields]") {
    TempDir d("fieldthreads");
    const std::string pts = write_points(d), D = d.path.string();
    std::ostringstream at;
    for (int i = 0; i < 9000; ++i) at << (i % 97) * 0.1 << " " << 100 + (i % 41) * 0.1 << " " << (i % 13) * 0.45 << "\n";
    spit(d / "at.txt", at.str());
    for (const std::string t : {"1", "3"}) {
        REQUIRE(sh("MESHLESS probe " + pts + " --field mpu --at-file " + D + "/at.txt -o " + D + "/p" + t + ".csv --threads " + t, d).code == 0);
        REQUIRE(sh("MESHLESS slice " + pts + " --plane y=102 --size 200x200 -o " + D + "/s" + t + ".png --threads " + t, d).code == 0);
        REQUIRE(sh("MESHLESS resample " + pts + " --grid 30,20,25 -o " + D + "/r" + t + ".nrrd --threads " + t, d).code == 0);
    }
    const std::string probe = slurp(d / "p1.csv");
    CHECK(probe == slurp(d / "p3.csv"));
    CHECK(std::count(probe.begin(), probe.end(), '\n') == 9001);
    CHECK(slurp(d / "s1.png") == slurp(d / "s3.png"));
    CHECK(slurp(d / "r1.nrrd") == slurp(d / "r3.nrrd"));
}
