// The one smoke test of meshless-bench (bench/): tiny sizes and one rep, a few seconds. It checks
// that the executable runs, prints its tables with ratios against baselines, writes its markdown
// only where told (a temporary folder), and that the whole-process harness turns a failing command
// into an "n/a (reason)" row instead of aborting. Timings are never asserted (they depend on the
// machine and its load); the benchmarks' numbers are the benchmarks' business, not the tests'.
#include <catch2/catch.hpp>

#include <filesystem>
#include <sstream>
#include <string>

#include "cli/cli_harness.hpp"

using namespace meshless::test;

namespace {

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

const std::string kBench = MESHLESS_BENCH_BINARY;

}  // namespace

TEST_CASE("meshless-bench smoke: process and accuracy --quick, markdown where told, bad usage", "[bench]") {
    TempDir dir("bench-smoke");
    const std::string md = (dir / "process.md").string();
    const std::filesystem::path work = dir / "work";
    std::filesystem::create_directories(work);
    const RunResult r = sh(kBench + " process --quick --data " + shared_data().string() + " --meshless " + meshless_exe() +
                               " --work " + work.string() + " --markdown " + md,
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = r.out;
    INFO(text);
    CHECK(contains(text, "Machine: "));
    CHECK(contains(text, "(e) splat throughput"));
    CHECK(contains(text, "M points/s"));
    // a command the binary refuses is an "n/a (reason)" row, not an abort; a binary that does not run skips the section
    spit(dir / "fake-meshless", "#!/bin/sh\n[ \"$1\" = --version ] && { echo fake 1.0; exit 0; }\n"
                                "echo \"meshless $1: unknown option '--fake'\" >&2; exit 1\n");
    std::filesystem::permissions(dir / "fake-meshless", std::filesystem::perms::owner_all);
    const RunResult na = sh(kBench + " process --quick --data " + (dir / "no-data").string() + " --meshless " +
                                (dir / "fake-meshless").string(), dir);
    INFO(na.err);
    CHECK(na.code == 0);
    CHECK(contains(na.out, "n/a (exit 1: unknown option '--fake')"));
    const RunResult gone = sh(kBench + " process --quick --meshless /bin/false", dir);
    CHECK(gone.code == 0);
    CHECK(contains(gone.out, "process section skipped"));
    if (have_shared_data()) {
        CHECK(contains(text, "(a) isosurface vs VTK Flying Edges"));
        CHECK(contains(text, "isosurface -o PLY"));
        CHECK(contains(text, "generate | project | write"));
        CHECK(contains(text, "isosurface --threads 2"));
        CHECK(contains(text, "A: extract STORE.mls | project | write"));
        CHECK(contains(text, "in-process"));
        CHECK(contains(text, "x  "));  // ratios printed as "1.23x"
        // pipes and threads write the same points as the in-process, one-thread command
        CHECK_FALSE(contains(text, "DIFFERENT"));
    } else {
        CHECK(contains(text, "Parts (a)-(d) skipped"));
    }
    // markdown only where told (part (e) runs without the shared data, (a)-(d) need it); the work
    // folder keeps its inputs and loses its outputs
    const std::string markdown = slurp(md);
    CHECK(contains(markdown, "| points | PLY MiB |"));
    CHECK(contains(markdown, "| row | seconds |") == have_shared_data());
    for (const auto& e : std::filesystem::directory_iterator(work)) {
        const std::string n = e.path().filename().string();
        CHECK((n.rfind("lung_", 0) == 0 || n.rfind("sphere_", 0) == 0));
    }

    const RunResult acc = sh(kBench + " accuracy --quick", dir);
    INFO(acc.err);
    CHECK(acc.code == 0);
    CHECK(contains(acc.out, "mean dist [vox]"));
    CHECK((contains(acc.out, "PASS") || contains(acc.out, "FAIL")));

    CHECK(sh(kBench + " nonsense", dir).code == 1);
    CHECK(sh(kBench + " speed --reps 0", dir).code == 1);
    const RunResult help = sh(kBench + " --help", dir);
    CHECK(help.code == 0);
    CHECK(contains(help.out, "usage: meshless-bench"));
}

TEST_CASE("meshless-bench smoke: render --quick ray casts, compares and keeps the bytes across threads", "[bench]") {
    TempDir dir("bench-render");
    const RunResult r = sh(kBench + " render --quick --data " + shared_data().string(), dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(contains(r.out, "Volume rendering: ray casting fields"));
    CHECK(contains(r.out, "M samples/s"));
    CHECK(contains(r.out, "PSNR vs volume dB"));
    CHECK(contains(r.out, "yes"));
    CHECK_FALSE(contains(r.out, "DIFFERENT"));
}

TEST_CASE("meshless-bench smoke: scattered --quick runs every part, peers in the same run, bad options refused", "[bench]") {
    TempDir dir("bench-scattered");
    const std::string md = (dir / "scattered.md").string();
    const std::filesystem::path work = dir / "work";
    std::filesystem::create_directories(work);
    const RunResult r = sh(kBench + " scattered --quick --peer-timeout 60 --data " + shared_data().string() + " --meshless " +
                               meshless_exe() + " --work " + work.string() + " --markdown " + md,
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = r.out;
    INFO(text);
    CHECK(contains(text, "(a) Accuracy against truth"));
    CHECK(contains(text, "(b) Table 5.1 rebuilt"));
    CHECK(contains(text, "(c) Scaling"));
    // every meshless command succeeded (a failing one is an "n/a (exit N: ...)" cell) and was measured
    CHECK_FALSE(contains(text, "n/a ("));
    CHECK(contains(text, "sphere uniform"));
    CHECK(contains(text, "gyroid layered"));
    CHECK(contains(text, "meshless"));
    const bool peers = sh("/usr/bin/python3 -c 'import numpy, scipy, vtk'", dir).code == 0;
    if (peers) {
        CHECK(contains(text, "SciPy griddata linear + flying edges"));
        CHECK(contains(text, "vtkDelaunay3D + vtkContourFilter"));
        CHECK(contains(text, "vtkPointInterpolator Gaussian + flying edges"));
        CHECK(contains(text, "x  "));  // ratios against meshless, "1.23x"
    }
    if (have_shared_data()) {
        CHECK(contains(text, "bucky"));
        CHECK(contains(text, "silicium"));
        CHECK(contains(text, "SAME"));  // 1 and 2 threads write the same point bytes
        CHECK_FALSE(contains(text, "DIFFERENT"));
    }
    // markdown only where told; the generated sets stay in the work folder, the outputs do not
    CHECK(contains(slurp(md), "| set | N | method |"));
    CHECK(std::filesystem::exists(work / "scattered" / "sets" / "sphere-uniform-3000.ply"));
    for (const auto& e : std::filesystem::directory_iterator(work / "scattered"))
        CHECK(e.path().filename().string().rfind("out-", 0) != 0);

    CHECK(sh(kBench + " scattered --sizes 5", dir).code == 1);
    CHECK(sh(kBench + " scattered --peer-timeout -1", dir).code == 1);
}

TEST_CASE("meshless-bench smoke: scale --quick runs the whole processes and builds and evaluates both fields", "[bench]") {
    if (!have_shared_data()) return;  // (LIDC2.vti is in the shared data folder)
    TempDir dir("bench-scale");
    const RunResult r = sh(kBench + " scale --quick --no-peers --sizes 5000 --sets ct,clustered --data " + shared_data().string() + " --meshless " + meshless_exe(), dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    INFO(r.out);
    CHECK(contains(r.out, "SAME"));  // the slab run wrote the one-slab run's bytes
    CHECK_FALSE(contains(r.out, "DIFFERENT"));
    CHECK(contains(r.out, "eval random Mpts/s"));
    CHECK(contains(r.out, "terms/query"));
    // one row per field, each with its numbers (a failed build or read is a "build: ..." / "read: ..." cell)
    const auto row_of = [&](const std::string& set, const std::string& field) {  // a table line "set 5000 <spaces> field ..."
        std::istringstream lines(r.out);
        for (std::string line; std::getline(lines, line);) {
            std::istringstream words(line);
            std::string k, n, f;
            if (words >> k >> n >> f && k == set && n == "5000" && f == field) return true;
        }
        return false;
    };
    for (const char* set : {"ct", "clustered"}) {
        INFO(set);
        CHECK(row_of(set, "mpu"));
        CHECK(row_of(set, "rbf-grid"));
    }
    CHECK_FALSE(contains(r.out, "build: "));
    CHECK_FALSE(contains(r.out, "read: "));
}
