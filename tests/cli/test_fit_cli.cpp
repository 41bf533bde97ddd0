// meshless fit and --field FILE.mlf from the command line: probe/slice/resample with a fitted field
// give the bytes they give when they build the field themselves (any --threads), the .mlf does not
// depend on the threads that fitted it, and a .mlf fitted to other data, damaged, or combined with
// fitting options is refused with the documented exit code and a one-line message.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "cli/cli_harness.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

/// n scattered points of a smooth field, CSV with a header.
std::string write_points(const TempDir& d, const std::string& name, int n, unsigned seed) {
    std::ostringstream s;
    s.precision(17);
    s << "x,y,z,value\n";
    unsigned r = seed;
    auto u = [&] { r = r * 1103515245u + 12345u; return (r >> 8) / double(1 << 24); };
    for (int i = 0; i < n; ++i) {
        const double x = u() * 10, y = u() * 4 + 100, z = u() * 6;
        s << x << "," << y << "," << z << "," << std::sin(x) * std::cos(0.5 * z) + 0.1 * y << "\n";
    }
    const auto p = d / name;
    spit(p, s.str());
    return p.string();
}

bool one_line(const std::string& err) { return !err.empty() && err.find('\n') == err.size() - 1; }

}  // namespace

TEST_CASE("probe, slice and resample with a .mlf give the bytes of the field they build, any --threads", "[cli][fit]") {
    TempDir d("fit_cli");
    const std::string pts = write_points(d, "pts.csv", 1500, 777), D = d.path.string();
    const std::string at = " --at 5,102,3 --at 2.5,101,1.5 --at 9.9,103.9,0.1 --at 20,20,20";
    for (const char* k : {"rbf-grid", "mpu", "global-rbf"}) {
        INFO(k);
        REQUIRE(sh("MESHLESS fit " + pts + " --field " + k + " -o " + D + "/f.mlf --threads 2", d).code == 0);
        REQUIRE(sh("MESHLESS fit " + pts + " --field " + k + " -o " + D + "/f1.mlf --threads 1", d).code == 0);
        CHECK(slurp(d / "f.mlf") == slurp(d / "f1.mlf"));
        for (const char* t : {"1", "2"}) {
            const auto built = sh("MESHLESS probe " + pts + " --field " + k + at + " --threads " + t, d);
            const auto loaded = sh("MESHLESS probe " + pts + " --field " + D + "/f.mlf" + at + " --threads " + t, d);
            REQUIRE(built.code == 0);
            REQUIRE(loaded.code == 0);
            CHECK(built.out.size() > 100);
            CHECK(loaded.out == built.out);
        }
        REQUIRE(sh("MESHLESS slice " + pts + " --field " + k + " --plane z=3 --size 96x96 -o " + D + "/a.png", d).code == 0);
        REQUIRE(sh("MESHLESS slice " + pts + " --field " + D + "/f.mlf --plane z=3 --size 96x96 -o " + D + "/b.png --threads 2", d).code == 0);
        CHECK(slurp(d / "a.png") == slurp(d / "b.png"));
        REQUIRE(sh("MESHLESS resample " + pts + " --field " + k + " --grid 12,10,8 -o " + D + "/a.nrrd", d).code == 0);
        REQUIRE(sh("MESHLESS resample " + pts + " --field " + D + "/f.mlf --grid 12,10,8 -o " + D + "/b.nrrd", d).code == 0);
        CHECK(slurp(d / "a.nrrd") == slurp(d / "b.nrrd"));
    }
    // non-default options travel in the file
    REQUIRE(sh("MESHLESS fit " + pts + " --field mpu --max-points 40 --alpha 0.9 --hardy-c 0.05 -o " + D + "/o.mlf", d).code == 0);
    const auto built = sh("MESHLESS probe " + pts + " --field mpu --max-points 40 --alpha 0.9 --hardy-c 0.05" + at, d);
    const auto loaded = sh("MESHLESS probe " + pts + " --field " + D + "/o.mlf" + at, d);
    CHECK(loaded.out == built.out);
    const auto info = sh("MESHLESS info " + D + "/o.mlf", d);
    REQUIRE(info.code == 0);
    CHECK_THAT(info.out, Catch::Contains("field: mpu"));
    CHECK_THAT(info.out, Catch::Contains("N = 40"));
    CHECK_THAT(info.out, Catch::Contains("alpha = 0.9"));
    CHECK_THAT(info.out, Catch::Contains("fitted to: 1500 points, identity hash "));
    CHECK_THAT(info.out, Catch::Contains("value: value, range "));
}

TEST_CASE("a .mlf fitted to other data, damaged, or mixed with fitting options is refused", "[cli][fit][mustfail]") {
    TempDir d("fit_bad");
    const std::string a = write_points(d, "a.csv", 400, 1), b = write_points(d, "b.csv", 400, 2), D = d.path.string();
    REQUIRE(sh("MESHLESS fit " + a + " --field mpu -o " + D + "/a.mlf", d).code == 0);
    auto r = sh("MESHLESS probe " + b + " --field " + D + "/a.mlf --at 5,102,3", d);
    CHECK(r.code == 2);
    CHECK(one_line(r.err));
    CHECK_THAT(r.err, Catch::Contains("a.mlf was fitted to other data: 400 points, hash "));
    CHECK_THAT(r.err, Catch::Contains("; these are 400 points, hash "));
    CHECK(r.out.empty());
    r = sh("MESHLESS probe " + a + " --field " + D + "/a.mlf --binning 7 --at 5,102,3", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--binning: the field comes fitted from"));
    // damaged: truncated, a flipped payload byte, another version
    const std::string good = slurp(d / "a.mlf");
    spit(d / "t.mlf", good.substr(0, good.size() / 2));
    r = sh("MESHLESS probe " + a + " --field " + D + "/t.mlf --at 5,102,3", d);
    CHECK(r.code == 2);
    CHECK(one_line(r.err));
    CHECK_THAT(r.err, Catch::Contains("t.mlf: offset 24: truncated"));
    std::string flipped = good;
    flipped[flipped.size() - 10] ^= 1;
    spit(d / "c.mlf", flipped);
    r = sh("MESHLESS info " + D + "/c.mlf", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("c.mlf: offset "));
    CHECK_THAT(r.err, Catch::Contains("payload checksum mismatch"));
    std::string newer = good;
    newer[8] = 2;
    spit(d / "v.mlf", newer);
    r = sh("MESHLESS probe " + a + " --field " + D + "/v.mlf --at 5,102,3", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("v.mlf: offset 8: made by a newer version of meshless"));
    // a missing .mlf
    r = sh("MESHLESS probe " + a + " --field " + D + "/missing.mlf --at 5,102,3", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("missing.mlf"));
}

TEST_CASE("meshless fit refuses outputs that are not a .mlf file and leaves nothing behind", "[cli][fit][mustfail]") {
    TempDir d("fit_out");
    const std::string a = write_points(d, "a.csv", 100, 3), D = d.path.string();
    CHECK(sh("MESHLESS fit " + a + " --field mpu -o " + D + "/x.ply", d).code == 1);
    CHECK(sh("MESHLESS fit " + a + " --field mpu -o -", d).code == 1);
    CHECK(sh("MESHLESS fit " + a + " --field mpu", d).code == 1);
    CHECK(sh("MESHLESS fit " + a + " --field nonsense -o " + D + "/x.mlf", d).code == 1);
    // field parameters out of range: the option is named (was the library's "hardy_c_rel > 0")
    for (const std::string opt : {"--hardy-c -1", "--hardy-c 0", "--hardy-c 1e300", "--hardy-c-world -2", "--hardy-c-world 1e300",
                                  "--hardy-c-spacing nan", "--hardy-c-rough -1", "--binning 0"}) {
        INFO(opt);
        const auto r = sh("MESHLESS fit " + a + " --field rbf-grid " + opt + " -o " + D + "/x.mlf", d);
        CHECK(r.code == 1);
        CHECK_THAT(r.err, Catch::Contains(opt.substr(0, opt.find(' ')) + ": expected a"));
    }
    REQUIRE(sh("MESHLESS fit " + a + " --field mpu -o " + D + "/x.mlf", d).code == 0);
    CHECK(sh("MESHLESS fit " + a + " --field " + D + "/x.mlf -o " + D + "/y.mlf", d).code == 1);
    CHECK(sh("MESHLESS fit " + D + "/missing.csv --field mpu -o " + D + "/z.mlf", d).code == 2);
    CHECK(sh("MESHLESS fit " + a + " --field mpu -o " + D + "/no/dir/z.mlf", d).code == 2);
    for (const auto& e : std::filesystem::directory_iterator(d.path)) {
        const std::string n = e.path().filename().string();
        CHECK((n == "a.csv" || n == "x.mlf" || n == "stderr.txt" || n == "stdout.txt"));
    }
}

TEST_CASE("fit reads multiblock inputs as the block commands do (PLOT3D combustor, VTS pieces)", "[cli][fit][real]") {
    if (!have_shared_data()) return;
    TempDir d("fit_blocks");
    const std::string P = (shared_data() / "plot3d").string(), D = d.path.string();
    const std::string comb = P + "/combxyz.bin --q " + P + "/combq.bin";
    REQUIRE(sh("MESHLESS fit " + comb + " --field mpu -o " + D + "/comb.mlf --stats", d).code == 0);
    const std::string at = " --at 3,0,25 --at 8,1,30 --at 12,-2,33";
    const auto built = sh("MESHLESS probe " + comb + " --field mpu" + at, d);
    const auto loaded = sh("MESHLESS probe " + comb + " --field " + D + "/comb.mlf" + at + " --threads 2", d);
    REQUIRE(built.code == 0);
    REQUIRE(loaded.code == 0);
    CHECK(loaded.out == built.out);
    const auto info = sh("MESHLESS info " + D + "/comb.mlf", d);
    CHECK_THAT(info.out, Catch::Contains("fitted to: 47025 points"));
    // another q component is other data
    const auto other = sh("MESHLESS probe " + comb + " --q-component 1 --field " + D + "/comb.mlf" + at, d);
    CHECK(other.code == 2);
    CHECK_THAT(other.err, Catch::Contains("was fitted to other data"));
    // the three VTS pieces of the combustor
    const std::string vts = P + "/multicomb_0.vts " + P + "/multicomb_1.vts " + P + "/multicomb_2.vts";
    REQUIRE(sh("MESHLESS fit " + vts + " --field rbf-grid -o " + D + "/mc.mlf", d).code == 0);
    const auto b2 = sh("MESHLESS probe " + vts + " --field rbf-grid" + at, d);
    const auto l2 = sh("MESHLESS probe " + vts + " --field " + D + "/mc.mlf" + at, d);
    REQUIRE(b2.code == 0);
    CHECK(l2.out == b2.out);
}
