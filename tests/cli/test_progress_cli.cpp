// Progress lines of the long-running commands (Unix habits): isosurface (volume in
// memory, slab-streamed, brick store, multiblock, scattered), mc (volume, brick store), render,
// verify, splat --turntable, hierarchy, fit and batch draw "meshless CMD: NN% RATE UNIT/s, ETA" on stderr and clear it at the end;
// --quiet draws nothing. MESHLESS_PROGRESS=always stands in for a terminal and drops the first
// second's delay (cli/progress_meter.hpp), so the line shows however fast the run is.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "../test_size.hpp"
#include "cli/cli_harness.hpp"

namespace fs = std::filesystem;
using namespace meshless;
using namespace meshless::test;

namespace {

// (spelled apart: the harness replaces the word MESHLESS with the binary's path)
const std::string kForce = "export M\"\"ESHLESS_PROGRESS=always; ";

// The command's progress: at least one line "\r\033[Kmeshless CMD: NN% ..." and the clearing "\r\033[K" last.
void check_progress(const std::string& cmd, const std::string& label, const std::string& unit, const TempDir& d) {
    INFO(cmd);
    const RunResult r = sh(kForce + cmd, d);
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);
    const std::string head = "\r\033[Kmeshless " + label + ": ";
    const auto at = r.err.find(head);
    CHECK(at != std::string::npos);
    if (at != std::string::npos) {
        const std::string line = r.err.substr(at + head.size(), r.err.find('\r', at + 1) - at - head.size());
        CHECK(line.find('%') != std::string::npos);
        if (!unit.empty()) CHECK(r.err.find(" " + unit + "/s") != std::string::npos);
    }
    CHECK(r.err.size() >= 4);
    CHECK(r.err.compare(r.err.size() - 4, 4, "\r\033[K") == 0);  // cleared at the end
    const RunResult q = sh(kForce + cmd + " --quiet", d);
    CHECK(q.code == 0);
    CHECK(q.err.find("meshless " + label + ":") == std::string::npos);
    CHECK(q.err.find('\r') == std::string::npos);
}

}  // namespace

TEST_CASE("progress lines: isosurface, mc and render on volumes and brick stores, and --quiet silences them", "[cli][progress]") {
    TempDir d("progress_cli");
    const std::string D = d.path.string();
    const std::string raw = write_uint8_analytic_volume(d, "ball", AnalyticField::sphere, 24, 200, 20);
    REQUIRE(sh("MESHLESS convert " + raw + " -o " + D + "/b.mlb --brick 8", d).code == 0);
    // the raw file is slab-streamed, the brick store read brick by brick
    check_progress("MESHLESS isosurface " + raw + " --iso 100.5 -o " + D + "/p.ply", "isosurface", "cell rows", d);
    check_progress("MESHLESS isosurface " + D + "/b.mlb --iso 100.5 -o " + D + "/p.ply --png " + D + "/p.png --size 32x32",
                   "isosurface", "cell rows", d);
    check_progress("MESHLESS mc " + raw + " --iso 100.5 -o " + D + "/m.ply", "mc", "cell layers", d);
    check_progress("MESHLESS mc " + D + "/b.mlb --iso 100.5 -o " + D + "/m.ply", "mc", "bricks", d);
    check_progress("MESHLESS render " + raw + " -o " + D + "/r.png --size 32x32", "render", "rays", d);
    check_progress("MESHLESS verify " + D + "/b.mlb", "verify", "bricks", d);
    // splat --turntable counts frames (points and a mesh); its timing line follows the cleared progress line
    for (const std::string& in : {D + "/p.ply", D + "/m.ply"}) {
        const std::string cmd = "MESHLESS splat " + in + " -o " + D + "/t.png --size 32x32 --turntable 3";
        INFO(cmd);
        const RunResult r = sh(kForce + cmd, d);
        CHECK(r.code == 0);
        CHECK(r.err.find("\r\033[Kmeshless splat: ") != std::string::npos);
        CHECK(r.err.find(" frames/s") != std::string::npos);
        const RunResult q = sh(kForce + cmd + " --quiet", d);
        CHECK(q.code == 0);
        CHECK(q.err.find('\r') == std::string::npos);
    }
    // without the forcing variable stderr is no terminal here: nothing drawn
    const RunResult plain = sh("MESHLESS isosurface " + raw + " --iso 100.5 -o " + D + "/p.ply", d);
    CHECK(plain.code == 0);
    CHECK(plain.err.find('\r') == std::string::npos);
}

TEST_CASE("progress lines: multiblock and scattered isosurfaces, fit and hierarchy", "[cli][progress]") {
    TempDir d("progress_cli_points");
    const std::string D = d.path.string();
    // scattered points: a 9x9x9 lattice of a linear field, as CSV
    {
        std::string csv = "x,y,z,v\n";
        for (int k = 0; k < 9; ++k)
            for (int j = 0; j < 9; ++j)
                for (int i = 0; i < 9; ++i)
                    csv += std::to_string(i + 0.1 * j) + "," + std::to_string(j + 0.1 * k) + "," + std::to_string(k) + "," +
                           std::to_string(i + j + k) + "\n";
        spit(d / "p.csv", csv);
    }
    check_progress("MESHLESS isosurface " + D + "/p.csv --iso 12 -o " + D + "/s.ply", "isosurface", "stencils", d);
    check_progress("MESHLESS fit " + D + "/p.csv -o " + D + "/p.mlf", "fit", "local fits", d);
    check_progress("MESHLESS hierarchy " + D + "/p.csv -o " + D + "/p.mlh", "hierarchy", "", d);
    // a --max-error build makes an unknown number of splits: it counts the samples settled in their leaves
    check_progress("MESHLESS hierarchy " + D + "/p.csv --max-error 0.5 -o " + D + "/pe.mlh", "hierarchy", "samples", d);
    if (test::reduced_test_sizes()) {  // (the combustor's field takes minutes instrumented: blocks of a small ball)
        const std::string ball = write_uint8_analytic_volume(d, "ball", AnalyticField::sphere, 16, 200.0, 0.0);
        REQUIRE(sh("MESHLESS split " + ball + " --layout overlapping -o " + D + "/b.vtm", d).code == 0);
        check_progress("MESHLESS isosurface " + D + "/b.vtm --iso 100.5 -o " + D + "/c.ply", "isosurface", "cells", d);
    } else if (have_shared_data()) {
        const std::string comb = (shared_data() / "plot3d/combxyz.bin").string();
        const std::string q = (shared_data() / "plot3d/combq.bin").string();
        check_progress("MESHLESS isosurface " + comb + " --q " + q + " --iso 0.4 -o " + D + "/c.ply", "isosurface", "cells", d);
    }
}

TEST_CASE("progress lines: batch shows the volume, its step and the batch's share with an ETA, --quiet silences it", "[cli][progress][batch]") {
    TempDir d("progress_batch");
    const std::string D = d.path.string();
    fs::create_directories(d.path / "arch");
    TempDir vols("progress_batch_vols");
    for (const char* n : {"a", "b"}) {
        const std::string raw = write_uint8_analytic_volume(vols, n, AnalyticField::sphere, 20, 200, 20);
        fs::copy_file(raw, d.path / "arch" / fs::path(raw).filename());
    }
    const std::string cmd = "MESHLESS batch " + D + "/arch -o " + D + "/out --iso 100.5";
    const RunResult r = sh(kForce + cmd, d);
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("\r\033[K[1/2] ") != std::string::npos);
    CHECK(r.err.find("\r\033[K[2/2] ") != std::string::npos);
    CHECK(r.err.find(": converting ") != std::string::npos);
    CHECK(r.err.find("; batch ") != std::string::npos);
    CHECK(r.err.find("%, ETA ") != std::string::npos);
    // --quiet (into a fresh output folder, so that the work is done again) draws nothing
    const RunResult q = sh(kForce + "rm -rf " + D + "/out; " + cmd + " --quiet", d);
    CHECK(q.code == 0);
    CHECK(q.err.find('\r') == std::string::npos);
}
