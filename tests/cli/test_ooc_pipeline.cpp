// Out-of-core iso-splatting from the command line: brick stores give the same points as the
// in-memory path, under --memory, across pipes, threads and MPI ranks; paradigm (A) from
// `generate --all`; rank failures fail the whole job without output.
#include <catch2/catch.hpp>

#include <tuple>

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "cli/cli_harness.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/ply_points.hpp"
#include "kernels/analytic_volumes.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

/// A 70^3 uint8 gyroid (several bricks of 32 cells) written with the name convention.
std::string gyroid_volume(const TempDir& d) {
    return write_uint8_analytic_volume(d, "gyroid", AnalyticField::gyroid, 70, 80.0, 128.0);
}

/// The records of a PLY point set, sorted bytewise (order-free comparison).
std::vector<std::string> sorted_records(const fs::path& p) {
    const auto pts = read_ply_points(p.string()).points;
    std::vector<std::string> r;
    for (const auto& x : pts) r.emplace_back(reinterpret_cast<const char*>(&x), sizeof x);
    std::sort(r.begin(), r.end());
    return r;
}


}  // namespace

TEST_CASE("a brick store gives the in-memory points, for any thread count, under a small --memory", "[cli][ooc-pipeline]") {
    TempDir d("oocp");
    const std::string vol = gyroid_volume(d), D = d.path.string();
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/g.mlb --brick 16", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 128.5 -o " + D + "/mem.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/g.mlb --iso 128.5 -o " + D + "/ooc.ply --memory 64K", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/g.mlb --iso 128.5 -o " + D + "/ooc3.ply --threads 3", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + D + "/g.mlb --iso 128.5 --memory 64K | MESHLESS project | MESHLESS write -o " + D + "/pipe.ply", d).code == 0);
    const auto mem = sorted_records(d / "mem.ply");
    REQUIRE(mem.size() > 1000);
    CHECK(sorted_records(d / "ooc.ply") == mem);  // same points; Morton brick order instead of row order
    CHECK(slurp(d / "ooc.ply") == slurp(d / "ooc3.ply"));
    CHECK(slurp(d / "ooc.ply") == slurp(d / "pipe.ply"));
    auto r = sh("MESHLESS isosurface " + D + "/g.mlb --iso 128.5 -o " + D + "/x.ply --memory 1K", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--memory"));
    CHECK(!fs::exists(d / "x.ply"));
}

TEST_CASE("paradigm (A): generate --all, extract, project at render time or in a stage", "[cli][ooc-pipeline]") {
    TempDir d("parAcli");
    const std::string vol = gyroid_volume(d), D = d.path.string();
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/g.mlb", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + D + "/g.mlb --all -o " + D + "/g.mls --memory 1M", d).code == 0);
    // the sample store recomputes samples from a brick store: a raw volume is refused, naming convert
    auto r0 = sh("MESHLESS generate " + vol + " --all -o " + D + "/g2.mls", d);
    CHECK(r0.code == 1);
    CHECK_THAT(r0.err, Catch::Contains("convert"));
    REQUIRE(sh("MESHLESS info " + D + "/g.mls | grep -q span-space", d).code == 0);
    for (const char* iso : {"100.5", "128.5", "200.5"}) {
        INFO(iso);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso " + std::string(iso) + " -o " + D + "/c.ply", d).code == 0);
        REQUIRE(sh("MESHLESS extract " + D + "/g.mls --iso " + std::string(iso) + " | MESHLESS project | MESHLESS write -o " + D + "/a.ply", d).code == 0);
        CHECK(sorted_records(d / "a.ply") == sorted_records(d / "c.ply"));
    }
    // paradigm (B): samples stored, projection at render time
    CHECK(sh("MESHLESS extract " + D + "/g.mls --iso 128.5 | MESHLESS splat -o " + D + "/b.png --size 64x64", d).code == 0);
    // the samples carry their cell corners: the exact projection gives paradigm (C)'s bytes
    REQUIRE(sh("MESHLESS extract " + D + "/g.mls --iso 128.5 | MESHLESS project --projection exact | MESHLESS write -o " + D +
                   "/ae.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/g.mlb --iso 128.5 --projection exact -o " + D + "/ce.ply", d).code == 0);
    CHECK(slurp(d / "ae.ply") == slurp(d / "ce.ply"));
    CHECK(sh("MESHLESS generate " + vol + " --all --iso 3 -o " + D + "/x.mls", d).code == 1);
}

TEST_CASE("mpirun -np 2 gives the single-process bytes, a failing rank fails the job with no output", "[cli][ooc-pipeline][mpi]") {
    TempDir d("mpi");
    const std::string mpirun = mpirun_prefix(d);
    if (mpirun.empty()) {
        WARN("mpirun not installed: MPI test skipped");
        return;
    }
    const std::string vol = gyroid_volume(d), D = d.path.string();
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/g.mlb --brick 16", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/g.mlb --iso 128.5 -o " + D + "/one.ply", d).code == 0);
    auto r = sh(mpirun + "MESHLESS isosurface " + D + "/g.mlb --iso 128.5 -o " + D + "/two.ply --stats", d);
    if (r.code != 0 && r.err.find("without MPI") != std::string::npos) {
        WARN("this build has no MPI: MPI test skipped");
        return;
    }
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("2 rank(s)"));
    CHECK(slurp(d / "one.ply") == slurp(d / "two.ply"));
    // three ranks (one owning fewer bricks), two threads each: the same bytes
    r = sh(mpirun_prefix(d, 3) + "MESHLESS isosurface " + D + "/g.mlb --iso 128.5 -o " + D +
               "/three.ply --threads 2 --memory 64K",
           d);
    REQUIRE(r.code == 0);
    CHECK(slurp(d / "one.ply") == slurp(d / "three.ply"));
    // an output option refused (rank 0 alone opens the outputs): found on every rank before any talks,
    // said once, exit 1, no rank left waiting
    r = sh(mpirun + "MESHLESS isosurface " + D + "/g.mlb --iso 128.5 -o " + D + "/x.vtp --ply-color value", d);
    CHECK(r.code == 1);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') >= 1);
    std::size_t said = 0;
    for (std::size_t at = r.err.find("--ply-color"); at != std::string::npos; at = r.err.find("--ply-color", at + 1)) ++said;
    CHECK(said == 1);
    CHECK(r.err.find("MPI_ABORT") == std::string::npos);
    // damage the last brick (rank 1's share): the job must fail and leave no two_bad.ply
    std::string store = slurp(d / "g.mlb");
    const auto size = store.size();
    store[size - 32 - 64 * 2 - 200] ^= 0x5a;  // inside the last bricks' frames, before index and footer
    spit(d / "bad.mlb", store);
    r = sh(mpirun + "MESHLESS isosurface " + D + "/bad.mlb --iso 128.5 -o " + D + "/two_bad.ply", d);
    CHECK(r.code != 0);
    CHECK(!fs::exists(d / "two_bad.ply"));
    // a sample store under mpirun: the usage error that names what MPI runs need (was "unrecognized
    // volume format" from every rank, then an MPI abort)
    REQUIRE(sh("MESHLESS generate " + D + "/g.mlb --all -o " + D + "/g.mls", d).code == 0);
    r = sh(mpirun + "MESHLESS isosurface " + D + "/g.mls --iso 128.5 -o " + D + "/two_mls.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("g.mls: MPI runs need a brick store (.mlb)"));
    CHECK_THAT(r.err, !Catch::Contains("unrecognized volume format"));
    CHECK(!fs::exists(d / "two_mls.ply"));
    // every other command runs in one process: refused under mpirun, said once, nothing written
    // (it would repeat the whole job on every rank); --help still answers
    for (const std::string& cmd : {"mc " + D + "/g.mlb --iso 128.5 -o " + D + "/two_mc.ply",
                                  "render " + D + "/g.mlb --size 32x32 -o " + D + "/two_mc.png",
                                  "info " + D + "/g.mlb"}) {
        INFO(cmd);
        r = sh(mpirun + "MESHLESS " + cmd, d);
        CHECK(r.code == 1);
        const std::string word = cmd.substr(0, cmd.find(' '));
        CHECK_THAT(r.err, Catch::Contains("meshless " + word + ": runs in one process, not under mpirun (this launch has 2 ranks"));
        CHECK(r.err.find("runs in one process") == r.err.rfind("runs in one process"));  // rank 0 alone says it
    }
    CHECK(!fs::exists(d / "two_mc.ply"));
    CHECK(!fs::exists(d / "two_mc.png"));
    r = sh(mpirun + "MESHLESS mc --help", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("usage: meshless mc"));
}

TEST_CASE("mpirun -np 2 batch: the volumes dealt to the ranks, one process's outputs and one summary", "[cli][ooc-pipeline][mpi]") {
    TempDir d("mpi-batch");
    const std::string mpirun = mpirun_prefix(d);
    if (mpirun.empty()) {
        WARN("mpirun not installed: MPI test skipped");
        return;
    }
    const fs::path arch = d / "archive";
    fs::create_directories(arch);
    const TempDir& dir = d;
    for (const auto& [name, field, n] : {std::tuple{"gyroid", AnalyticField::gyroid, 48}, std::tuple{"ball", AnalyticField::sphere, 40},
                                        std::tuple{"small", AnalyticField::gyroid, 24}}) {
        const std::string v = write_uint8_analytic_volume(dir, name, field, n, 80.0, 128.0);
        fs::rename(v, arch / fs::path(v).filename());
    }
    spit(arch / "broken_8x8x8_uint8.raw", std::string(100, 'x'));  // too short: fails, on whichever rank
    const std::string A = arch.string(), D = d.path.string();
    const RunResult one = sh("MESHLESS batch " + A + " -o " + D + "/one --iso 128.5 --iso 150.5", d);
    CHECK(one.code == 2);
    RunResult two = sh(mpirun + "MESHLESS batch " + A + " -o " + D + "/two --iso 128.5 --iso 150.5", d);
    if (two.code != 2 && two.err.find("without MPI") != std::string::npos) {
        WARN("this build has no MPI: MPI test skipped");
        return;
    }
    INFO(two.err);
    CHECK(two.code == 2);
    // one summary (rank 0's), every volume in archive order, the broken one failed
    CHECK(two.out.find("4 volume(s): 3 done, 0 up to date, 1 failed") != std::string::npos);
    CHECK(two.out.find("4 volume(s)") == two.out.rfind("4 volume(s)"));
    CHECK(two.out.find("ball") < two.out.find("broken"));
    CHECK(two.out.find("broken") < two.out.find("gyroid"));
    CHECK(two.out.find("gyroid") < two.out.find("small"));
    // the outputs of one process, byte for byte (stores and point sets)
    int compared = 0;
    for (const auto& e : fs::directory_iterator(d / "one")) {
        const std::string ext = e.path().extension().string();
        if (ext != ".ply" && ext != ".mlb") continue;
        INFO(e.path().filename());
        REQUIRE(fs::exists(d / "two" / e.path().filename()));
        CHECK(slurp(e.path()) == slurp(d / "two" / e.path().filename()));
        ++compared;
    }
    CHECK(compared == 9);  // 3 stores, 2 isovalues each
    // a rerun finds everything up to date on every rank
    two = sh(mpirun + "MESHLESS batch " + A + " -o " + D + "/two --iso 128.5 --iso 150.5", d);
    CHECK(two.out.find("4 volume(s): 0 done, 3 up to date, 1 failed") != std::string::npos);
    // --shard is for runs without mpirun
    const RunResult shard = sh(mpirun + "MESHLESS batch " + A + " -o " + D + "/three --iso 128.5 --shard 1/2", d);
    CHECK(shard.code == 1);
    CHECK(shard.err.find("--shard is for runs without mpirun") != std::string::npos);
}

TEST_CASE("mc on a brick store welds the seams: the in-memory vertex set and triangle count", "[cli][ooc-pipeline]") {
    TempDir d("oocmc");
    const std::string vol = gyroid_volume(d), D = d.path.string();
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/g.mlb --brick 16", d).code == 0);
    REQUIRE(sh("MESHLESS mc " + vol + " --iso 128.5 -o " + D + "/mem.ply", d).code == 0);
    REQUIRE(sh("MESHLESS mc " + D + "/g.mlb --iso 128.5 -o " + D + "/ooc.ply --memory 64K", d).code == 0);
    const Mesh a = read_ply_mesh((d / "mem.ply").string()), b = read_ply_mesh((d / "ooc.ply").string());
    CHECK(a.triangle_count() == b.triangle_count());
    REQUIRE(a.vertex_count() == b.vertex_count());
    auto positions = [](const Mesh& m) {
        std::vector<std::array<float, 3>> p(m.vertex_count());
        for (std::size_t i = 0; i < p.size(); ++i) p[i] = {m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]};
        std::sort(p.begin(), p.end());
        return p;
    };
    CHECK(positions(a) == positions(b));
}

TEST_CASE("a brick store is a VOLUME everywhere: re-bricking, sampling, synth", "[cli][ooc-pipeline]") {
    TempDir d("mlbvol");
    const std::string vol = gyroid_volume(d), D = d.path.string();
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/g32.mlb", d).code == 0);
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/g16.mlb --brick 16", d).code == 0);
    REQUIRE(sh("MESHLESS convert " + D + "/g32.mlb -o " + D + "/g16b.mlb --brick 16", d).code == 0);
    CHECK(slurp(d / "g16.mlb") == slurp(d / "g16b.mlb"));
    REQUIRE(sh("MESHLESS sample " + vol + " --count 500 --seed 3 -o " + D + "/a.csv", d).code == 0);
    REQUIRE(sh("MESHLESS sample " + D + "/g32.mlb --count 500 --seed 3 -o " + D + "/b.csv", d).code == 0);
    CHECK(slurp(d / "a.csv") == slurp(d / "b.csv"));
    // the store read brick by brick through a one-brick cache, the points grouped by brick: the same points
    REQUIRE(sh("MESHLESS sample " + D + "/g16.mlb --count 500 --seed 3 --memory 1K -o " + D + "/c.csv", d).code == 0);
    CHECK(slurp(d / "a.csv") == slurp(d / "c.csv"));
    REQUIRE(sh("MESHLESS synth --upsample 2 " + D + "/g32.mlb -o " + D + "/s1.mlb", d).code == 0);
    REQUIRE(sh("MESHLESS synth --upsample 2 " + vol + " -o " + D + "/s2.mlb", d).code == 0);
    CHECK(slurp(d / "s1.mlb") == slurp(d / "s2.mlb"));    spit(d / "garbage.mlb", std::string(1000, '\x42'));
    const auto r = sh("MESHLESS isosurface " + D + "/garbage.mlb --iso 1 -o " + D + "/x.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("not a brick store"));
}

TEST_CASE("mc runs as a graph: same bytes for any --threads, in memory and from a brick store", "[cli][ooc-pipeline][mc]") {
    TempDir d("mcthreads");
    const std::string vol = gyroid_volume(d), D = d.path.string();
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/g.mlb --brick 16", d).code == 0);
    for (const std::string& in : {vol, D + "/g.mlb"}) {
        REQUIRE(sh("MESHLESS mc " + in + " --iso 128.5 -o " + D + "/t1.ply --threads 1", d).code == 0);
        REQUIRE(sh("MESHLESS mc " + in + " --iso 128.5 -o " + D + "/t3.ply --threads 3 --memory 64K", d).code == 0);
        CHECK(slurp(d / "t1.ply") == slurp(d / "t3.ply"));
        CHECK(read_ply_mesh((d / "t1.ply").string()).triangle_count() > 1000);
    }
}
