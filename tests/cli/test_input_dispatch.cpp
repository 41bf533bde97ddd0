// Which reader a command picks for its input, and what it says when the input cannot serve: a .raw
// that --dims describes is a volume (info as for the volume commands), positions-only points are
// refused by every command that needs values, `-` is a volume for render and convert (spooled) and
// refused, with the reason, where point sets are read by extension; the demo writes a folder, never
// to standard output.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_harness.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {
// A 16^3 uint16 big-endian ramp without the name convention (v.raw): only --dims and --type say
// what it is.
std::string write_plain_raw(const TempDir& d) {
    std::string b;
    for (int k = 0; k < 16; ++k)
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i) {
                const int v = 100 * (i + j + k);
                b += static_cast<char>(v >> 8);
                b += static_cast<char>(v & 255);
            }
    const std::string path = (d / "v.raw").string();
    spit(path, b);
    return path;
}
}  // namespace

TEST_CASE("info: a .raw described by --dims is a raw volume", "[cli][info]") {
    TempDir d("dispatch-info");
    const std::string raw = write_plain_raw(d);
    const auto r = sh("MESHLESS info " + raw + " --dims 16,16,16 --type uint16 --endian big --value-range", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("raw volume"));
    CHECK_THAT(r.out, Catch::Contains("dims: 16 x 16 x 16"));
    CHECK_THAT(r.out, Catch::Contains("type: uint16"));
    CHECK_THAT(r.out, Catch::Contains("value range: 0 .. 4500"));  // big-endian read right
    CHECK_THAT(r.out, !Catch::Contains("point set"));
    // a mesh: its faces counted beside its vertices
    REQUIRE(sh("MESHLESS mc " + raw + " --dims 16,16,16 --type uint16 --endian big --iso 2000 -o " + d.path.string() + "/m.ply", d).code == 0);
    const auto m = sh("MESHLESS info " + d.path.string() + "/m.ply", d);
    REQUIRE(m.code == 0);
    CHECK_THAT(m.out, Catch::Matches("(.|\\n)*\\n  [1-9][0-9]* faces\\n(.|\\n)*"));
}

TEST_CASE("positions-only points are refused by every command that needs values", "[cli][scatter]") {
    TempDir d("dispatch-positions");
    std::string csv = "x,y,z\n";
    for (int i = 0; i < 40; ++i) csv += std::to_string(i % 4) + "," + std::to_string((i / 4) % 5) + "," + std::to_string(i / 20) + "\n";
    spit(d / "p.csv", csv);
    const std::string P = (d / "p.csv").string(), D = d.path.string();
    for (const std::string& cmd : std::vector<std::string>{"fit -o " + D + "/f.mlf", "probe --at 1,1,0.5", "slice --plane z=0.5 -o " + D + "/s.png",
                                  "resample --grid 8,8,8 -o " + D + "/r.nrrd", "render -o " + D + "/r.png",
                                  "hierarchy -o " + D + "/h.mlh", "isosurface --iso 1 -o " + D + "/i.ply"}) {
        INFO(cmd);
        const std::string verb = cmd.substr(0, cmd.find(' '));
        const auto r = sh("MESHLESS " + verb + " " + P + cmd.substr(cmd.find(' ')), d);
        CHECK(r.code == 2);
        CHECK_THAT(r.err, Catch::Contains(P + ": the points carry no values (positions only); meshless " + verb + " needs a value"));
    }
    for (const char* out : {"f.mlf", "s.png", "r.nrrd", "r.png", "h.mlh", "i.ply"}) CHECK(!std::filesystem::exists(d / out));
}

TEST_CASE("standard input: a volume for render and convert and refused where points are read by extension", "[cli][stdin]") {
    TempDir d("dispatch-stdin");
    const std::string raw = write_plain_raw(d), D = d.path.string();
    const std::string nrrd = D + "/v.nrrd";
    spit(nrrd, "NRRD0004\ntype: ushort\nendian: big\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n\n" + slurp(raw));
    REQUIRE(sh("MESHLESS convert " + nrrd + " -o " + D + "/file.mlb", d).code == 0);
    REQUIRE(sh("MESHLESS convert - -o " + D + "/pipe.mlb < " + nrrd, d).code == 0);
    CHECK(slurp(d / "file.mlb") == slurp(d / "pipe.mlb"));
    REQUIRE(sh("MESHLESS render " + nrrd + " --size 64x64 -o " + D + "/file.png", d).code == 0);
    REQUIRE(sh("cat " + nrrd + " | MESHLESS render - --size 64x64 -o " + D + "/pipe.png", d).code == 0);
    CHECK(slurp(d / "file.png") == slurp(d / "pipe.png"));
    const auto h = sh("MESHLESS hierarchy - -o " + D + "/h.mlh < " + nrrd, d);
    CHECK(h.code == 1);
    CHECK_THAT(h.err, Catch::Contains("reads its data (point sets, volumes, multiblock sets) from files"));
    const auto demo = sh("cd " + D + " && MESHLESS demo -o -", d);
    CHECK(demo.code == 1);
    CHECK_THAT(demo.err, Catch::Contains("-o -: the demo writes a folder"));
    CHECK(!std::filesystem::exists(d / "-"));
}

TEST_CASE("help: -h on a subcommand and the help text's own placeholders", "[cli][help]") {
    TempDir d("dispatch-help");
    const auto h = sh("MESHLESS isosurface -h", d);
    CHECK(h.code == 0);
    CHECK_THAT(h.out, Catch::StartsWith("usage: meshless isosurface VOLUME"));
    const auto p = sh("MESHLESS isosurface POINTS --help", d);
    CHECK(p.code == 0);
    CHECK_THAT(p.out, Catch::StartsWith("usage: meshless isosurface POINTS"));
    const auto b = sh("MESHLESS isosurface BLOCKS --help", d);
    CHECK(b.code == 0);
    CHECK_THAT(b.out, Catch::StartsWith("usage: meshless isosurface BLOCKS"));
    CHECK(sh("MESHLESS probe -h", d).code == 0);
}
