// .npy 3-D arrays through the volume commands (formats/npy_volume.hpp): the same samples as a raw
// file named by the convention (the oracle: the raw path) give the same bytes from isosurface, mc,
// convert, render and info's statistics; C order, Fortran order and big endian alike; --spacing
// applies as for raw files and draws no warning; a 2-D .npy stays a point set.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>

#include "cli/cli_harness.hpp"
#include "npy_test_data.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

std::string npy_header(const std::string& descr, bool fortran, const std::string& shape) {
    return npy_prefix("{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") + ", 'shape': " + shape + ", }");
}

// Lines naming the input (PLY comments, the stream's producer) differ between vol.npy and the raw file.
std::string without_names(const std::string& bytes) { return lines_without(bytes, "vol"); }

}  // namespace

TEST_CASE("npy volumes: isosurface, mc, convert, render and info give the raw file's results", "[cli][npy]") {
    TempDir d("npy-cli");
    const std::string D = d.path.string() + "/";
    const std::string raw = write_uint8_analytic_volume(d, "vol", AnalyticField::torus, 24, 200.0, 0.0);
    const std::string samples = slurp(raw);
    spit(d.path / "vol.npy", npy_header("|u1", false, "(24, 24, 24)") + samples);
    {  // the same volume as Fortran-order big-endian uint16: values equal, x still fastest
        std::string be;
        for (unsigned char c : samples) be += std::string{'\0', static_cast<char>(c)};
        spit(d.path / "volf.npy", npy_header(">u2", true, "(24, 24, 24)") + be);
    }
    const RunResult info = sh("MESHLESS info " + D + "vol.npy", d);
    INFO(info.err);
    REQUIRE(info.code == 0);
    CHECK(info.out.find("npy") != std::string::npos);
    CHECK(info.out.find("dims: 24 x 24 x 24") != std::string::npos);
    struct Cmd {
        std::string args, out;
    };
    const Cmd cmds[] = {
        {"isosurface IN --iso 100.5 -o OUT", "i.ply"},
        {"isosurface IN --iso 100.5 --spacing 0.5,1,2 -o OUT", "s.ply"},
        {"mc IN --iso 100.5 -o OUT", "m.ply"},
        {"convert IN -o OUT", "c.mlb"},
        {"render IN --size 48x48 -o OUT", "r.png"},
    };
    for (const Cmd& c : cmds)
        for (const char* npy : {"vol.npy", "volf.npy"}) {
            std::string results[2];
            for (int k = 0; k < 2; ++k) {
                std::string line = "MESHLESS " + c.args;
                line.replace(line.find("IN"), 2, k == 0 ? D + npy : raw);
                const std::string out = D + std::to_string(k) + c.out;
                line.replace(line.find("OUT"), 3, out);
                const RunResult r = sh(line, d);
                INFO(line << ": " << r.err);
                REQUIRE(r.code == 0);
                CHECK(r.err.find("warning") == std::string::npos);  // --spacing is not "ignored"
                results[k] = slurp(out);
            }
            INFO(c.args << " " << npy);
            CHECK(!results[0].empty());
            if (std::string(npy) == "volf.npy" && c.out == "c.mlb") continue;  // a uint16 store, not a uint8 one
            CHECK(without_names(results[0]) == without_names(results[1]));
        }
    // a 2-D .npy is a point set: fit reads it, a volume command names the dispatch
    std::string pts = npy_header("<f4", false, "(8, 4)");
    for (int i = 0; i < 32; ++i) {
        const float v = static_cast<float>((i * 7) % 11);
        pts += std::string(reinterpret_cast<const char*>(&v), 4);
    }
    spit(d.path / "pts.npy", pts);
    const RunResult mc = sh("MESHLESS mc " + D + "pts.npy --iso 1 -o " + D + "x.ply", d);
    CHECK(mc.code == 2);
    CHECK(mc.err.find("pts.npy: .npy shape (8, 4) is not a volume") != std::string::npos);
}
