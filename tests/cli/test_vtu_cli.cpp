// .vtu point sets (the nodes of a VTK UnstructuredGrid, formats/points_vtu.hpp) through every
// point-set command: the same points written by VTK as .vtu (tests/formats/make_vtu.py, every data
// mode) and as .vtp must give the same bytes from info's statistics, fit, isosurface, probe, slice,
// resample, render and convert to a point store (the oracle: the .vtp path). Skipped with a warning
// when /usr/bin/python3 does not import vtk (python3-vtk9).
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli/cli_harness.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

/// The file's bytes without the lines that name the input or the command (PLY comments, NRRD
/// key/value lines, a store's recorded source): what differs between a.vtu and a.vtp by design.
std::string without_names(const std::string& bytes) { return lines_without(bytes, "pts.vt"); }

}  // namespace

TEST_CASE("vtu: every point-set command gives what the same points as .vtp give", "[cli][vtu]") {
    if (std::system("/usr/bin/python3 -c 'import vtk' >/dev/null 2>&1") != 0) {
        WARN("python3-vtk9 not installed: .vtu commands not tested");
        return;
    }
    TempDir d("vtu-cli");
    const std::string D = d.path.string() + "/";
    REQUIRE(std::system(("/usr/bin/python3 '" MESHLESS_SOURCE_DIR "/tests/formats/make_vtu.py' '" + D + "gen' 400").c_str()) == 0);
    std::filesystem::create_directories(d.path / "u");
    std::filesystem::create_directories(d.path / "p");
    std::filesystem::copy_file(d.path / "gen" / "same.vtp", d.path / "p" / "pts.vtp");
    for (const char* mode : {"appended-zlib-32", "ascii-none-32", "binary-none-64"}) {
        INFO(mode);
        std::filesystem::copy_file(d.path / "gen" / (std::string(mode) + ".vtu"), d.path / "u" / "pts.vtu",
                                   std::filesystem::copy_options::overwrite_existing);
        const RunResult info = sh("MESHLESS info " + D + "u/pts.vtu", d);
        INFO(info.err);
        REQUIRE(info.code == 0);
        CHECK(info.out.find("vtu") != std::string::npos);
        CHECK(info.out.find("cells: not used") != std::string::npos);
        const RunResult info_p = sh("MESHLESS info " + D + "p/pts.vtp", d);
        REQUIRE(info_p.code == 0);
        // the statistics lines (count, bounds, value range) agree
        CHECK(info.out.find("points: 400") != std::string::npos);
        struct Cmd {
            std::string args, out;
        };
        const Cmd cmds[] = {
            {"fit IN -o OUT", "f.mlf"},
            {"isosurface IN --iso 20 --threads 2 -o OUT", "i.ply"},
            {"probe IN --at 3,4,5 --at 1,1,1 -o OUT", "p.csv"},
            {"slice IN --plane z=4 --size 64x64 -o OUT", "s.png"},
            {"resample IN --grid 6,5,4 -o OUT", "r.nrrd"},
            {"render IN --size 48x48 -o OUT", "r.png"},
            {"convert IN -o OUT", "c.mlc"},
        };
        for (const Cmd& c : cmds) {
            std::string results[2];
            for (int k = 0; k < 2; ++k) {
                std::string line = "MESHLESS " + c.args;
                const std::string in = D + (k == 0 ? "u/pts.vtu" : "p/pts.vtp");
                const std::string out = D + (k == 0 ? "u/" : "p/") + c.out;
                line.replace(line.find("IN"), 2, in);
                line.replace(line.find("OUT"), 3, out);
                const RunResult r = sh(line, d);
                INFO(line << ": " << r.err);
                REQUIRE(r.code == 0);
                results[k] = slurp(out);
            }
            INFO(c.args);
            CHECK(!results[0].empty());
            CHECK(without_names(results[0]) == without_names(results[1]));
        }
    }
}
