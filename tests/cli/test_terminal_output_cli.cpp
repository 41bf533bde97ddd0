// Binary outputs are never written to a terminal: "-o -" (or "--png -") with standard output on a
// terminal is a usage error, for every command that writes binary bytes (streams, PLY, VTP, PNG,
// NRRD), while text outputs (CSV) still reach it. The terminal is a pseudo-terminal from
// script(1) (util-linux/bsdutils); without it the test says so and passes nothing.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "cli_harness.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

TEST_CASE("binary outputs refuse a terminal, text outputs reach it", "[cli][tty]") {
    TempDir d("tty");
    if (!have_command("script", d)) {
        WARN("no script(1): the terminal cases were not run");
        return;
    }
    const std::string vol = write_uint8_analytic_volume(d, "torus", AnalyticField::torus, 20, 200.0, 0.0);
    const std::string ply = (d / "t.ply").string();
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + ply, d).code == 0);
    // script -e: the command's exit status; its terminal output is script's standard output
    auto on_tty = [&](const std::string& cmd) { return sh("script -qec \"" + cmd + "\" /dev/null", d); };
    const struct {
        std::string cmd, what;
    } binary[] = {
        {"MESHLESS isosurface " + vol + " --iso 100.5 -o -", "an oriented point set"},
        {"MESHLESS isosurface " + vol + " --iso 100.5 -o " + (d / "a.ply").string() + " --png -", "a PNG image"},
        {"MESHLESS mc " + vol + " --iso 100.5 -o -", "a triangle mesh"},
        {"MESHLESS splat " + ply + " -o -", "a PNG image"},
        {"MESHLESS generate " + vol + " --iso 100.5", "a binary stream"},
        {"MESHLESS isosurface " + vol + " --iso 100.5 -o - --format vtp", "an oriented point set"},
    };
    for (const auto& b : binary) {
        INFO(b.cmd);
        const auto r = on_tty(b.cmd);
        CHECK(r.code == 1);
        CHECK_THAT(r.out, Catch::Contains("refusing to write " + b.what + " to a terminal"));
        CHECK(r.out.find("ply\nformat") == std::string::npos);
        CHECK(r.out.find("\x89PNG") == std::string::npos);
    }
    // text: the CSV of a probe reaches the terminal
    const auto csv = on_tty("MESHLESS probe " + ply + " --at 10,10,10 --field mpu");
    CHECK(csv.code == 0);
    CHECK_THAT(csv.out, Catch::Contains("x,y,z,value"));
    // and piped, the binary bytes flow as before
    CHECK(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o - | cmp - " + ply, d).code == 0);
}

TEST_CASE("a picture of a volume without patient's axes notes how to turn the camera, on a terminal only", "[cli][tty]") {
    TempDir d("tty-axes");
    if (!have_command("script", d)) {
        WARN("no script(1): the terminal cases were not run");
        return;
    }
    const std::string vol = write_uint8_analytic_volume(d, "torus", AnalyticField::torus, 20, 200.0, 0.0);
    auto on_tty = [&](const std::string& cmd) { return sh("script -qec \"" + cmd + "\" /dev/null", d); };
    const std::string note = "says nothing of the patient's axes";
    for (const std::string& cmd : {"MESHLESS isosurface " + vol + " --iso 100.5 --png " + (d / "t.png").string(),
                                   "MESHLESS render " + vol + " --size 32x32 -o " + (d / "r.png").string()}) {
        INFO(cmd);
        const auto tty = on_tty(cmd);
        CHECK(tty.code == 0);
        CHECK_THAT(tty.out, Catch::Contains(note) && Catch::Contains("--up, --view, --azimuth and --elevation turn the camera"));
        const auto piped = sh(cmd, d);  // not a terminal: no chatter
        CHECK(piped.code == 0);
        CHECK(piped.err.find(note) == std::string::npos);
        CHECK(on_tty(cmd + " --up z").out.find(note) == std::string::npos);  // the user chose the camera
    }
    // a header that says where the patient's axes point: no note
    spit(d / "h.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nspace: right-anterior-superior\nsizes: 20 20 20\n"
                       "space directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nencoding: raw\ndata file: " +
                           fs::path(vol).filename().string() + "\n");
    CHECK(on_tty("MESHLESS isosurface " + (d / "h.nhdr").string() + " --iso 100.5 --png " + (d / "h.png").string()).out.find(note) ==
          std::string::npos);
}
