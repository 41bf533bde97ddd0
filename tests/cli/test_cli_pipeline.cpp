// The meshless command line as a user runs it: pipes vs in-process byte identity, thread-count
// identity, exit codes, bad input, quiet exit on closed pipes, no half-written outputs.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <vector>

#include "cli/cli_harness.hpp"
#include "formats/nrrd_writer.hpp"
#include "kernels/analytic_volumes.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

/// A 40^3 uint8 torus volume written with the name convention; returns its path.
std::string write_test_volume(const TempDir& d) {
    return write_uint8_analytic_volume(d, "torus", AnalyticField::torus, 40, 200.0, 0.0);
}

}  // namespace

TEST_CASE("pipes give the same bytes as the in-process isosurface, for any thread count", "[cli]") {
    TempDir d("pipe");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    for (const char* proj : {"approx", "exact", "none"}) {
        INFO(proj);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 --projection " + std::string(proj) + " -o " + D + "/a.ply --png " + D +
                       "/a.png --size 200x200",
                   d).code == 0);
        REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project --projection " + std::string(proj) +
                       " | MESHLESS write -o " + D + "/b.ply",
                   d).code == 0);
        REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 --threads 2 --compress | MESHLESS project --threads 3 --projection " +
                       std::string(proj) + " | MESHLESS splat -o " + D + "/b.png --size 200x200",
                   d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 --threads 2 --projection " + std::string(proj) + " -o " + D + "/c.ply", d).code == 0);
        const std::string a = slurp(d / "a.ply");
        CHECK(a.size() > 1000);
        CHECK(a == slurp(d / "b.ply"));
        CHECK(a == slurp(d / "c.ply"));
        CHECK(slurp(d / "a.png") == slurp(d / "b.png"));
    }
}

TEST_CASE("sample streams travel cell-indexed for every sample type and for brick stores: same bytes as in-process", "[cli]") {
    TempDir d("pipe-cells");
    const std::string D = d.path.string();
    // float32 (origin -1, spacing 2/39), int16 (negative values) and a brick store of a uint8 volume
    Volume f = make_analytic_volume(AnalyticField::gyroid, 40);
    write_nrrd(f, D + "/f.nrrd");
    Volume s;
    s.grid = f.grid;
    s.type = SampleType::i16;
    s.bytes = SampleBytes(static_cast<std::size_t>(f.grid.voxel_count()) * 2);
    const float* fv = reinterpret_cast<const float*>(f.bytes.data());
    for (std::int64_t i = 0; i < f.grid.voxel_count(); ++i) {
        const auto v = static_cast<std::int16_t>(std::lround(fv[i] * 3000.0));
        std::memcpy(s.bytes.data() + 2 * i, &v, 2);
    }
    write_nrrd(s, D + "/s.nrrd");
    const std::string vol = write_test_volume(d);
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/v.mlb --brick 16", d).code == 0);
    struct Case {
        std::string input, iso, per_record;
    };
    for (const Case& c : {Case{D + "/f.nrrd", "0.1", "bytes, 38."}, Case{D + "/s.nrrd", "-200.5", "bytes, 22."},
                         Case{D + "/v.mlb", "50.5", "bytes, 14."}}) {
        INFO(c.input);
        REQUIRE(sh("MESHLESS isosurface " + c.input + " --iso " + c.iso + " -o " + D + "/a.ply", d).code == 0);
        REQUIRE(sh("MESHLESS generate " + c.input + " --iso " + c.iso + " --threads 2 -o " + D + "/s.mls", d).code == 0);
        REQUIRE(sh("MESHLESS project " + D + "/s.mls | MESHLESS write -o " + D + "/b.ply", d).code == 0);
        const std::string a = slurp(d / "a.ply");
        CHECK(a.size() > 1000);
        CHECK(a == slurp(d / "b.ply"));
        const RunResult info = sh("MESHLESS info " + D + "/s.mls", d);
        REQUIRE(info.code == 0);
        CHECK_THAT(info.out, Catch::Matchers::Contains(c.per_record));  // payload bytes per record
        CHECK_THAT(info.out, !Catch::Matchers::Contains("(0 cell-indexed"));
    }
}

TEST_CASE("isosurface writes to /dev/stdout: into the pipe or the file standard output is", "[cli]") {
    TempDir d("devstdout");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/a.ply --png " + D + "/a.png --size 100x100", d).code == 0);
    // a pipe (stdout names no file to replace: written directly)
    auto r = sh("MESHLESS isosurface " + vol + " --iso 50.5 -o /dev/stdout | cat > " + D + "/b.ply", d);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
    r = sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/c.ply --png /dev/stdout --size 100x100 | cat > " + D + "/c.png", d);
    CHECK(r.code == 0);
    // a file (a name without an extension: the format is said)
    r = sh("MESHLESS isosurface " + vol + " --iso 50.5 -o /dev/stdout --format ply > " + D + "/e.ply", d);
    CHECK(r.code == 0);
    const std::string a = slurp(d / "a.ply");
    CHECK(a.size() > 1000);
    CHECK(slurp(d / "b.ply") == a);
    CHECK(slurp(d / "e.ply") == a);
    CHECK(slurp(d / "c.png") == slurp(d / "a.png"));
}

TEST_CASE("closed pipes end quietly, truncated streams are reported", "[cli]") {
    TempDir d("head");
    const std::string vol = write_test_volume(d);
    auto r = sh("MESHLESS generate " + vol + " --iso 50.5 | head -c 100 > /dev/null", d);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
    r = sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project | head -c 100 > /dev/null", d);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
    r = sh("MESHLESS generate " + vol + " --iso 50.5 | head -c 1000 | MESHLESS project > /dev/null", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("truncated"));
}

TEST_CASE("isosurface -o and --png: one failing output leaves the other's previous file and a closed stdout the named file complete", "[cli]") {
    TempDir d("twoout");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string(), run = "MESHLESS isosurface " + vol + " --iso 50.5 --size 64x64 ";
    REQUIRE(sh(run + "-o " + D + "/ref.ply --png " + D + "/ref.png", d).code == 0);
    // a PNG that cannot be created or written: exit 2, the previous -o file untouched, no temporaries
    spit(d / "keep.ply", "previous");
    auto r = sh(run + "-o " + D + "/keep.ply --png " + D + "/nodir/x.png", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("nodir/x.png"));
    CHECK(slurp(d / "keep.ply") == "previous");
    if (fs::exists("/dev/full")) {
        r = sh(run + "-o " + D + "/keep.ply --png /dev/full", d);
        CHECK(r.code == 2);
        CHECK(slurp(d / "keep.ply") == "previous");
    }
    // one output on a pipe whose reader has gone (`| true` exits before anything is written: the
    // write meets EPIPE, whatever the pipe buffer holds): quiet, the named file complete
    r = sh(run + "-o " + D + "/a.ply --png - | true", d);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
    CHECK(slurp(d / "a.ply") == slurp(d / "ref.ply"));
    r = sh(run + "-o - --png " + D + "/a.png | true", d);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
    CHECK(slurp(d / "a.png") == slurp(d / "ref.png"));
    for (const auto& e : fs::directory_iterator(d.path)) CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
}

TEST_CASE("garbage, wrong-version and wrong-kind streams are refused with exit code 2", "[cli]") {
    TempDir d("garbage");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    auto r = sh("echo hello | MESHLESS project > /dev/null", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("not a meshless point stream"));
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 -o " + D + "/s.mls", d).code == 0);
    std::string s = slurp(d / "s.mls");
    s[8] = 9;
    spit(d / "v9.mls", s);
    r = sh("MESHLESS project " + D + "/v9.mls > /dev/null", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("version 9"));
    r = sh("MESHLESS write " + D + "/s.mls -o " + D + "/x.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("unprojected"));
    CHECK(!fs::exists(d / "x.ply"));
    r = sh("MESHLESS project < /dev/null > /dev/null", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("empty input"));
}

TEST_CASE("bad volumes and bad arguments: one-line errors and documented exit codes", "[cli]") {
    TempDir d("bad");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    auto r = sh("MESHLESS isosurface " + vol + " -o " + D + "/x.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--iso"));
    r = sh("MESHLESS isosurface " + vol + " --iso abc -o " + D + "/x.ply", d);
    CHECK(r.code == 1);
    r = sh("MESHLESS isosurface " + vol + " --iso 5 --bogus -o " + D + "/x.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("unknown option"));
    r = sh("MESHLESS frobnicate", d);
    CHECK(r.code == 1);
    // wrong dims for the file size
    r = sh("MESHLESS isosurface " + vol + " --dims 41,40,40 --type uint8 --iso 5 -o " + D + "/x.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains(vol));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    // unreadable input, directory as input
    r = sh("MESHLESS isosurface " + D + "/missing_8x8x8_uint8.raw --iso 5 -o " + D + "/x.ply", d);
    CHECK(r.code == 2);
    r = sh("MESHLESS isosurface " + D + " --iso 5 -o " + D + "/x.ply", d);
    CHECK(r.code == 2);
    CHECK(!fs::exists(d / "x.ply"));
    // unwritable output: directory missing -> no file, exit 2
    r = sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/no/such/dir/x.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("no/such/dir/x.ply"));
    // a directory where the output file should be
    fs::create_directory(d / "dir.ply");
    r = sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/dir.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("is a directory"));
    // outputs are chosen by extension: point sets go to .ply or .vtp only, a PNG never to a .jpg
    for (const std::string& args : {std::string(" -o ") + D + "/x.xyz", std::string(" --png ") + D + "/x.jpg"}) {
        r = sh("MESHLESS isosurface " + vol + " --iso 50.5" + args, d);
        CHECK(r.code == 1);
        CHECK_THAT(r.err, Catch::Contains("chosen by extension"));
    }
    CHECK(!fs::exists(d / "x.xyz"));
    CHECK(!fs::exists(d / "x.jpg"));
    r = sh("MESHLESS mc " + vol + " --iso 50.5 -o " + D + "/m.obj", d);
    CHECK(r.code == 1);
    CHECK(!fs::exists(d / "m.obj"));
    // nothing half-written anywhere
    for (const auto& e : fs::directory_iterator(d.path)) CHECK(e.path().string().find(".tmp-") == std::string::npos);
}

TEST_CASE("an isovalue outside the data range warns and writes empty but valid outputs", "[cli]") {
    TempDir d("range");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    auto r = sh("MESHLESS isosurface " + vol + " --iso 1000 -o " + D + "/e.ply --png " + D + "/e.png --size 64x64", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("outside the data range"));
    CHECK_THAT(slurp(d / "e.ply"), Catch::Contains("element vertex 0\n"));
    CHECK(fs::file_size(d / "e.png") > 0);
    r = sh("MESHLESS info " + D + "/e.ply", d);
    CHECK(r.code == 0);
}

TEST_CASE("every subcommand answers --help with exit 0", "[cli]") {
    TempDir d("help");
    for (const char* c : {"demo", "isosurface", "generate", "project", "write", "splat", "mc", "info"}) {
        INFO(c);
        CHECK(sh("MESHLESS " + std::string(c) + " --help | grep -q usage:", d).code == 0);
    }
    CHECK(sh("MESHLESS --help | grep -q isosurface", d).code == 0);
}

TEST_CASE("demo writes a PLY and a PNG", "[cli]") {
    TempDir d("demo");
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS demo -o " + D + "/out --n 48 --size 160x120", d).code == 0);
    CHECK(fs::file_size(d / "out/demo.ply") > 10000);
    CHECK(fs::file_size(d / "out/demo.png") > 1000);
    auto r = sh("MESHLESS info " + D + "/out/demo.png " + D + "/out/demo.ply", d);
    CHECK(r.code == 0);
    // -o with a file's extension is refused, not made a folder of that name
    r = sh("MESHLESS demo -o " + D + "/pic.png --n 16", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("give a folder name"));
    CHECK_FALSE(fs::exists(d / "pic.png"));
}

TEST_CASE("demo equals isosurface on the same analytic volume: PLY and PNG bytes", "[cli]") {
    // The demo builds its volume in memory and runs the isosurface graph; here the same volume is
    // written as NRRD (float32, exact origin and spacing) and `meshless isosurface` streams it from
    // the file slab by slab. Only the PLY's source comment may differ.
    TempDir d("demoiso");
    const std::string D = d.path.string();
    auto without_source = [](std::string ply) {
        const auto at = ply.find("comment source ");
        REQUIRE(at != std::string::npos);
        return ply.erase(at, ply.find('\n', at) + 1 - at);
    };
    for (AnalyticField f : {AnalyticField::torus, AnalyticField::gyroid}) {
        INFO(to_string(f));
        const std::string vol = D + "/" + to_string(f) + ".nrrd";
        write_nrrd(make_analytic_volume(f, 40), vol);
        char iso[32];
        std::snprintf(iso, sizeof iso, "%.17g", default_iso(f));
        const std::string cam = " --size 96x72 --zoom 1.3 --azimuth 40";
        REQUIRE(sh("MESHLESS demo -o " + D + "/demo --field " + to_string(f) + " --n 40 --threads 2" + cam, d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso " + iso + " -o " + D + "/i.ply --png " + D + "/i.png --threads 1" + cam,
                   d).code == 0);
        const std::string demo_ply = slurp(d / "demo/demo.ply");
        CHECK(demo_ply.find("comment source demo-" + std::string(to_string(f))) != std::string::npos);
        CHECK(without_source(demo_ply) == without_source(slurp(d / "i.ply")));
        CHECK(slurp(d / "demo/demo.png") == slurp(d / "i.png"));
        // the comparison can fail: another view is another picture
        REQUIRE(sh("MESHLESS demo -o " + D + "/demo2 --field " + to_string(f) + " --n 40 --size 96x72 --zoom 1.3", d).code == 0);
        CHECK(slurp(d / "demo2/demo.png") != slurp(d / "i.png"));
    }
}

TEST_CASE("mc writes a closed mesh and stats, turntable writes N frames", "[cli]") {
    TempDir d("mc");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    auto r = sh("MESHLESS mc " + vol + " --iso 50.5 -o " + D + "/m.ply --stats", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("triangles"));
    r = sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/p.ply && MESHLESS splat " + D + "/p.ply -o " + D +
               "/t.png --turntable 4 --size 64x64 --kernel quad",
           d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("ms/frame"));
    for (int i = 0; i < 4; ++i) CHECK(fs::exists(d / ("t_00" + std::to_string(i) + ".png")));
}

TEST_CASE("unknown sample types and NaN voxels from the command line", "[cli]") {
    TempDir d("types");
    const std::string D = d.path.string();
    // a float32 sphere-ish ramp with a NaN plane through the middle
    const int n = 16;
    std::vector<float> f(n * n * n);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                f[i + n * (j + n * k)] = k == n / 2 ? std::numeric_limits<float>::quiet_NaN()
                                                    : static_cast<float>(std::sqrt((i - 7.5) * (i - 7.5) + (j - 7.5) * (j - 7.5) + (k - 7.3) * (k - 7.3)));
    spit(d / "v.raw", std::string(reinterpret_cast<const char*>(f.data()), f.size() * 4));
    auto r = sh("MESHLESS isosurface " + D + "/v.raw --dims 16,16,16 --type float64 --iso 5 -o " + D + "/x.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("unknown sample type"));
    r = sh("MESHLESS isosurface " + D + "/v.raw --dims 16,16,16 --type float32 --iso 5.5 -o " + D + "/x.ply --stats", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("cells with NaN/Inf skipped"));
    CHECK_THAT(r.err, !Catch::Contains(" 0 cells with NaN/Inf skipped"));
    r = sh("MESHLESS mc " + D + "/v.raw --dims 16,16,16 --type float32 --iso 5.5 -o " + D + "/m.ply --stats", d);
    CHECK(r.code == 0);
}

TEST_CASE("outputs that are devices, FIFOs or symlinks are written through, never replaced", "[cli]") {
    TempDir d("devs");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o /dev/null --png /dev/null", d).code == 0);
    CHECK(fs::is_character_file("/dev/null"));
    REQUIRE(sh("mkfifo " + D + "/fifo.ply && (cat " + D + "/fifo.ply > " + D + "/got.ply &) && MESHLESS isosurface " + vol +
                   " --iso 50.5 -o " + D + "/fifo.ply && sleep 0.2",
               d).code == 0);
    CHECK(fs::is_fifo(d / "fifo.ply"));
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/plain.ply", d).code == 0);
    CHECK(slurp(d / "got.ply") == slurp(d / "plain.ply"));
    REQUIRE(sh("ln -s plain.ply " + D + "/link.ply && MESHLESS isosurface " + vol + " --iso 60.5 -o " + D + "/link.ply", d).code == 0);
    CHECK(fs::is_symlink(d / "link.ply"));
    CHECK(slurp(d / "link.ply") != slurp(d / "got.ply"));  // the target was replaced with the new surface
}

TEST_CASE("misuse is refused: extra arguments, NaN numbers, same output twice, concatenated streams", "[cli]") {
    TempDir d("misuse");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    CHECK(sh("MESHLESS isosurface " + vol + " extra.raw --iso 50.5 -o " + D + "/x.ply", d).code == 1);
    CHECK(sh("MESHLESS isosurface " + vol + " --iso nan -o " + D + "/x.ply", d).code == 1);
    CHECK(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/x.ply --azimuth inf --png " + D + "/x.png", d).code == 1);
    CHECK(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/x.ply --png " + D + "/x.ply", d).code == 1);
    CHECK(!fs::exists(d / "x.ply"));
    // the PLY and the PNG are one outcome: a PNG that cannot be written takes the PLY with it
    CHECK(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/x.ply --png " + D + "/no/dir/x.png", d).code == 2);
    CHECK(!fs::exists(d / "x.ply"));
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project -o " + D + "/p.mlp", d).code == 0);
    auto r = sh("cat " + D + "/p.mlp " + D + "/p.mlp | MESHLESS write -o " + D + "/c.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("after the END frame"));
    r = sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project --iso 70.5 > /dev/null", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("differs from the stream's isovalue"));
    r = sh("MESHLESS isosurface ../x.nhdr --dims 5,5,5 --iso 1 -o " + D + "/x.ply", d);
    CHECK(r.code == 2);
    // outputs named for another format than the one written: refused before any work, nothing written
    for (const std::string& cmd : {"generate " + vol + " --iso 50.5 -o " + D + "/s.ply", "project " + D + "/p.mlp -o " + D + "/s.CSV",
                                   "convert " + vol + " -o " + D + "/s.zip", "probe " + vol + " --at 1,1,1 -o " + D + "/s.json"}) {
        r = sh("MESHLESS " + cmd, d);
        CHECK(r.code == 1);
        CHECK_THAT(r.err, Catch::Contains("-o '" + D + "/s."));
    }
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/v.mlb", d).code == 0);
    CHECK(sh("MESHLESS generate " + D + "/v.mlb --all -o " + D + "/s.bin", d).code == 1);
    CHECK(sh("MESHLESS generate " + vol + " --iso 50.5 -o " + D + "/.ply", d).code == 0);  // a hidden name, no extension
    fs::remove(d / ".ply");
    for (const auto& e : fs::directory_iterator(d.path)) CHECK(e.path().filename().string().rfind("s.", 0) != 0);
}

TEST_CASE("render-time projection (paradigms B/D) and PLY re-renders match the in-process picture", "[cli]") {
    TempDir d("bd");
    const std::string vol = write_test_volume(d);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "/a.ply --png " + D + "/a.png --size 120x90", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS splat -o " + D + "/b.png --size 120x90", d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "/a.ply -o " + D + "/c.png --size 120x90", d).code == 0);
    CHECK(slurp(d / "a.png") == slurp(d / "b.png"));
    CHECK(slurp(d / "a.png") == slurp(d / "c.png"));
    auto r = sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project | MESHLESS splat --iso 3 -o " + D + "/e.png", d);
    CHECK(r.code == 1);
}
