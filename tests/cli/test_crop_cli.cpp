// --crop X0,Y0,Z0,X1,Y1,Z1 on the volume commands (kernels/volume_crop.hpp, ooc/cropped_slice_source.hpp):
// the oracle is the cropped samples written by hand as a VTK legacy volume whose ORIGIN is the crop's
// first sample. isosurface (streamed raw file, volume in memory, brick store read through the bricks the
// crop touches), mc, convert, generate | project | write and render give that file's bytes and
// pixels; a crop that keeps fewer than 2 samples along an axis, a malformed one, and one given to
// points are usage errors (exit 1).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli/cli_harness.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

const std::string& kTooth = kToothRaw;

std::string body(const std::string& ply) { return ply.substr(ply.find("end_header\n")); }

}  // namespace

TEST_CASE("crop: --crop gives the bytes of the cropped samples written as a file of their own", "[cli][crop]") {
    if (!std::filesystem::exists(kTooth)) {
        WARN("skipped: " << kTooth << " is absent");
        return;
    }
    TempDir d("crop-cli");
    const std::string D = d.path.string() + "/";
    // the crop 10..60.5 x 20..80 x 29.5..120: samples x 10..60, y 20..80, z 30..120
    const std::string crop = "--crop 10,20,29.5,60.5,80,120";
    {
        const std::string all = slurp(kTooth);
        std::string cut;
        for (int z = 30; z <= 120; ++z)
            for (int y = 20; y <= 80; ++y) cut += all.substr(static_cast<std::size_t>((z * 94 + y) * 103 + 10), 51);
        // VTK legacy: an origin and no patient axes, as the raw file (MetaImage and NRRD would add axes)
        std::ofstream(D + "cut.vtk", std::ios::binary) << "# vtk DataFile Version 3.0\ncut\nBINARY\nDATASET STRUCTURED_POINTS\n"
                                                          "DIMENSIONS 51 61 91\nSPACING 1 1 1\nORIGIN 10 20 30\nPOINT_DATA 283101\n"
                                                          "SCALARS s unsigned_char 1\nLOOKUP_TABLE default\n"
                                                       << cut;
    }
    REQUIRE(sh("MESHLESS convert " + kTooth + " -o " + D + "tooth.mlb", d).code == 0);
    struct Case {
        std::string args, out;
    };
    const Case cases[] = {
        {"isosurface IN --iso 100.5 -o OUT", "i.ply"},
        {"isosurface IN --iso 60.5 --threads 2 --png OUT.png -o OUT", "t.ply"},
        {"mc IN --iso 100.5 -o OUT", "m.ply"},
        {"convert IN -o OUT", "c.mlb"},
        {"render IN --size 96x96 --tf ct-bone -o OUT", "r.png"},
    };
    for (const Case& c : cases) {
        std::string want_line = "MESHLESS " + c.args;
        want_line.replace(want_line.find("IN"), 2, D + "cut.vtk");
        while (want_line.find("OUT") != std::string::npos) want_line.replace(want_line.find("OUT"), 3, D + "want" + c.out);
        const RunResult w = sh(want_line, d);
        INFO(want_line << ": " << w.err);
        REQUIRE(w.code == 0);
        const std::string want = slurp(D + "want" + c.out);
        for (const std::string& in : {kTooth, D + "tooth.mlb"}) {
            std::string line = "MESHLESS " + c.args + " " + crop;
            line.replace(line.find("IN"), 2, in);
            while (line.find("OUT") != std::string::npos) line.replace(line.find("OUT"), 3, D + "got" + c.out);
            const RunResult g = sh(line, d);
            INFO(line << ": " << g.err);
            REQUIRE(g.code == 0);
            const std::string got = slurp(D + "got" + c.out);
            if (c.out.ends_with(".ply")) CHECK(body(got) == body(want));
            else CHECK(got == want);
            if (c.out == "t.ply") CHECK(slurp(D + "got" + c.out + ".png") == slurp(D + "want" + c.out + ".png"));
        }
    }
    // sample: scattered samples of the crop only (the same generator and seed as of the cropped file)
    REQUIRE(sh("MESHLESS sample " + kTooth + " --count 2000 " + crop + " -o " + D + "s.csv", d).code == 0);
    REQUIRE(sh("MESHLESS sample " + D + "cut.vtk --count 2000 -o " + D + "want_s.csv", d).code == 0);
    CHECK(slurp(D + "s.csv") == slurp(D + "want_s.csv"));
    // the stages joined by pipes give the in-process bytes
    const RunResult piped = sh("MESHLESS generate " + kTooth + " --iso 100.5 " + crop + " | MESHLESS project | MESHLESS write -o " + D +
                                   "p.ply",
                               d);
    INFO(piped.err);
    REQUIRE(piped.code == 0);
    CHECK(body(slurp(D + "p.ply")) == body(slurp(D + "wanti.ply")));
}

TEST_CASE("crop: an empty or malformed box and a box given to points are usage errors", "[cli][crop]") {
    TempDir d("crop-cli-bad");
    const std::string D = d.path.string() + "/";
    {
        std::string v(4 * 4 * 4, '\0');
        for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<char>(i);
        std::ofstream(D + "v_4x4x4_uint8.raw", std::ios::binary) << v;
        std::ofstream(D + "p.csv") << "x,y,z,v\n0,0,0,1\n1,0,0,2\n0,1,0,3\n0,0,1,4\n1,1,1,5\n";
    }
    struct Bad {
        std::string args, message;
    };
    const Bad bad[] = {
        {"isosurface V --iso 10 --crop 0,0,0,0.5,3,3 -o O.ply", "the crop keeps 1 sample(s) along x (the volume spans 0 to 3)"},
        {"isosurface V --iso 10 --crop 5,0,0,9,3,3 -o O.ply", "the crop keeps 0 sample(s) along x"},
        {"mc V --iso 10 --crop 0,0,0,3,3 -o O.ply", "--crop: expected X0,Y0,Z0,X1,Y1,Z1"},
        {"convert V --crop 0,0,nan,3,3,3 -o O.mlb", "--crop"},
        {"isosurface V --iso 10 --crop 3,0,0,0,3,3 -o O.ply", "crop along x from 3 to 0: expected finite numbers, the first at most the second"},
        {"render " + D + "p.csv --crop 0,0,0,1,1,1 -o O.png", "--crop applies to volumes"},
    };
    for (const Bad& b : bad) {
        std::string line = "MESHLESS " + b.args;
        if (line.find(" V ") != std::string::npos) line.replace(line.find(" V "), 3, " " + D + "v_4x4x4_uint8.raw ");
        while (line.find(" O.") != std::string::npos) line.replace(line.find(" O."), 3, " " + D + "out.");
        const RunResult r = sh(line, d);
        INFO(line << ": " << r.err);
        CHECK(r.code == 1);
        CHECK(r.err.find(b.message) != std::string::npos);
        CHECK_FALSE(std::filesystem::exists(D + "out.ply"));
    }
}
