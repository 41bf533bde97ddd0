// Empty results a script can see: an isovalue outside the data warns in one line naming the input
// and exits 0; with --fail-empty isosurface, mc and generate exit 4 (the empty outputs still
// written, valid); batch's summary counts the volumes with empty point sets and exits 4 under
// --fail-empty (2 still wins when a volume failed); render of an isosurface's points (one value
// everywhere) warns that the picture is all background.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>

#include "cli/cli_harness.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {
std::size_t lines(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }
}  // namespace

TEST_CASE("empty isosurfaces: one warning line and exit 0, --fail-empty exits 4 with the outputs written", "[cli][empty]") {
    TempDir d("empty-results");
    const std::string D = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "vol", AnalyticField::torus, 20, 200.0, 0.0);
    const std::string name = std::filesystem::path(vol).filename().string();
    // scattered points for the chapter-5 isosurface: a 6^3 lattice, value x + y + z (0 .. 15)
    std::string csv = "x,y,z,value\n";
    for (int k = 0; k < 6; ++k)
        for (int j = 0; j < 6; ++j)
            for (int i = 0; i < 6; ++i)
                csv += std::to_string(i) + "," + std::to_string(j) + "," + std::to_string(k) + "," + std::to_string(i + j + k) + "\n";
    spit(d.path / "pts.csv", csv);
    struct Cmd {
        std::string line, out, input, ok_iso;  // line: ISO stands for the isovalue
    };
    const Cmd cmds[] = {
        {"MESHLESS isosurface " + vol + " --iso ISO -o " + D + "i.ply", D + "i.ply", name, "100.5"},
        {"MESHLESS mc " + vol + " --iso ISO -o " + D + "m.ply", D + "m.ply", name, "100.5"},
        {"MESHLESS generate " + vol + " --iso ISO -o " + D + "g.mlp", D + "g.mlp", name, "100.5"},
        {"MESHLESS isosurface " + D + "pts.csv --iso ISO -o " + D + "p.ply", D + "p.ply", "pts.csv", "7.5"},
    };
    auto with_iso = [](std::string line, const std::string& iso) { return line.replace(line.find("ISO"), 3, iso); };
    for (const Cmd& c : cmds) {
        for (int fail = 0; fail < 2; ++fail) {
            std::filesystem::remove(c.out);
            const std::string line = with_iso(c.line, "300") + (fail ? " --fail-empty" : "");
            const RunResult r = sh(line, d);
            INFO(line << ": " << r.err);
            CHECK(r.code == (fail ? 4 : 0));
            CHECK(lines(r.err) == 1);
            CHECK(r.err.find(c.input) != std::string::npos);
            CHECK(r.err.find("outside the data range") != std::string::npos);
            CHECK(std::filesystem::exists(c.out));  // valid and empty
            if (c.out.size() > 4 && c.out.substr(c.out.size() - 4) == ".ply" && c.out != D + "m.ply")
                CHECK(slurp(c.out).find("element vertex 0") != std::string::npos);
        }
        // a surface that is not empty: exit 0 with --fail-empty, nothing on stderr
        const std::string ok = with_iso(c.line, c.ok_iso) + " --fail-empty";
        const RunResult r = sh(ok, d);
        INFO(ok << ": " << r.err);
        CHECK(r.code == 0);
        CHECK(r.err.empty());
    }
}

TEST_CASE("batch: the summary counts empty point sets, --fail-empty exits 4, a failure still exits 2", "[cli][empty][batch]") {
    TempDir d("empty-batch");
    const std::string D = d.path.string() + "/";
    std::filesystem::create_directories(d.path / "a");
    TempDir sub("empty-batch-a");
    const std::string vol = write_uint8_analytic_volume(sub, "vol", AnalyticField::torus, 20, 200.0, 0.0);
    std::filesystem::copy_file(vol, d.path / "a" / std::filesystem::path(vol).filename());
    RunResult r = sh("MESHLESS batch " + D + "a -o " + D + "out --iso 100.5 --iso 300 --quiet", d);
    INFO(r.out << r.err);
    CHECK(r.code == 0);
    CHECK(r.out.find("empty at 1 isovalue(s)") != std::string::npos);
    CHECK(r.out.find("1 with empty point sets") != std::string::npos);
    // again, everything up to date: the same count, and --fail-empty exits 4
    r = sh("MESHLESS batch " + D + "a -o " + D + "out --iso 100.5 --iso 300 --quiet --fail-empty", d);
    INFO(r.out << r.err);
    CHECK(r.code == 4);
    CHECK(r.out.find("up to date") != std::string::npos);
    CHECK(r.out.find("empty at 1 isovalue(s)") != std::string::npos);
    // no empty isovalue: 0
    CHECK(sh("MESHLESS batch " + D + "a -o " + D + "out --iso 100.5 --quiet --fail-empty", d).code == 0);
    // a failed volume beside it: 2
    spit(d.path / "a" / "bad_8x8x8_uint8.raw", "short");
    CHECK(sh("MESHLESS batch " + D + "a -o " + D + "out --iso 100.5 --iso 300 --quiet --fail-empty", d).code == 2);
    // an archive without volumes: a warning naming it, exit 0, or 4 with --fail-empty
    std::filesystem::create_directories(d.path / "none");
    const auto none = sh("MESHLESS batch " + D + "none -o " + D + "out2 --iso 100.5 --quiet", d);
    CHECK(none.code == 0);
    CHECK(none.err.find("meshless batch: warning: " + D + "none: no volumes") != std::string::npos);
    CHECK(sh("MESHLESS batch " + D + "none -o " + D + "out2 --iso 100.5 --quiet --fail-empty", d).code == 4);
}

TEST_CASE("render of an isosurface's points warns that the picture is all background", "[cli][empty][render]") {
    TempDir d("empty-render");
    const std::string D = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "vol", AnalyticField::torus, 20, 200.0, 0.0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "iso.ply", d).code == 0);
    const RunResult r = sh("MESHLESS render " + D + "iso.ply --size 32x32 -o " + D + "r.png", d);
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(r.err.find("iso.ply: the picture is all background") != std::string::npos);
    CHECK(lines(r.err) == 1);
    // the volume itself renders something: no warning
    const RunResult v = sh("MESHLESS render " + vol + " --size 32x32 -o " + D + "v.png", d);
    CHECK(v.code == 0);
    CHECK(v.err.find("all background") == std::string::npos);
}
