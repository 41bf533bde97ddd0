// The point store (.mlc) from the command line: convert POINTS... -o pts.mlc, verify, info, every
// point-set command reading it; exit codes (a --memory too small for one brick: 1; a damaged store:
// one line naming the file and the brick, 2, nothing written); the same bytes for any --threads and
// --memory; no temporaries after SIGINT/SIGTERM/SIGHUP, and after SIGKILL none once the next run swept.
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "cli_harness.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

std::string bucky() { return (shared_data() / "bucky" / "Bucky_32x32x32_uint8.raw").string(); }
std::string lidc2() { return (shared_data() / "vtkjs_LIDC2" / "LIDC2.vti").string(); }

std::vector<std::string> temporaries(const fs::path& dir) {
    std::vector<std::string> r;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos) r.push_back(e.path().filename().string());
    return r;
}

/// The records of a binary PLY's body, sorted (the multiset of its points).
std::vector<std::string> sorted_records(const std::string& bytes, std::size_t record_bytes) {
    const std::size_t body = bytes.find("end_header\n") + 11;
    std::vector<std::string> r;
    for (std::size_t at = body; at + record_bytes <= bytes.size(); at += record_bytes) r.push_back(bytes.substr(at, record_bytes));
    std::sort(r.begin(), r.end());
    return r;
}

/// meshless ARGS in dir, stdout/stderr to files, default signal dispositions.
pid_t spawn(const std::vector<std::string>& args, const TempDir& dir) {
    std::vector<std::string> all = {meshless_exe()};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (o < 0 || e < 0) ::_exit(121);
        ::dup2(o, 1);
        ::dup2(e, 2);
        for (int s : {SIGINT, SIGTERM, SIGHUP}) ::signal(s, SIG_DFL);
        sigset_t none;
        sigemptyset(&none);
        ::sigprocmask(SIG_SETMASK, &none, nullptr);
        ::execv(argv[0], argv.data());
        ::_exit(122);
    }
    return pid;
}

int wait_code(pid_t pid) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : WEXITSTATUS(status);
}

/// Waits (up to 2 minutes) until a temporary of `out` exists; false when the process exited first.
bool wait_for_temporary(pid_t pid, const fs::path& out) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    const std::string prefix = out.filename().string() + ".tmp-" + std::to_string(pid);
    while (std::chrono::steady_clock::now() < deadline) {
        for (const auto& e : fs::directory_iterator(out.parent_path()))
            if (e.path().filename().string().rfind(prefix, 0) == 0) return true;
        int status = 0;
        if (::waitpid(pid, &status, WNOHANG) == pid) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

}  // namespace

TEST_CASE("convert POINTS -o pts.mlc: verify, info, the same bytes for any --threads and --memory", "[cli][point_store]") {
    if (!have_shared_data()) return;
    TempDir dir("mlc-cli");
    const std::string ply = (dir / "p.ply").string(), csv = (dir / "p.csv").string();
    REQUIRE(sh("MESHLESS sample " + bucky() + " --count 60000 -o " + ply, dir).code == 0);
    REQUIRE(sh("MESHLESS sample " + bucky() + " --count 1000 --seed 2 -o " + csv, dir).code == 0);
    const std::string ref = (dir / "ref.mlc").string();
    auto r = sh("MESHLESS convert " + ply + " " + csv + " -o " + ref + " --brick-points 256 --stats -j 1", dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("61000 points") != std::string::npos);
    const std::string bytes = slurp(ref);
    for (const char* opts : {"-j 2", "--memory 10M -j 1", "--memory 10M -j 2", "--memory 12M -j 2"}) {
        INFO(opts);
        const std::string out = (dir / "o.mlc").string();
        r = sh(std::string("MESHLESS convert ") + ply + " " + csv + " -o " + out + " --brick-points 256 --stats " + opts, dir);
        INFO(r.err);
        REQUIRE(r.code == 0);
        if (std::string(opts).find("--memory") != std::string::npos) CHECK(r.err.find(" 0 sorted runs") == std::string::npos);
        CHECK(slurp(out) == bytes);
    }
    r = sh("MESHLESS verify " + ref, dir);
    CHECK(r.code == 0);
    CHECK(r.out.rfind("ok: 61000 points in ", 0) == 0);
    r = sh("MESHLESS info " + ref, dir);
    CHECK(r.code == 0);
    CHECK(r.out.find("point-store point set") != std::string::npos);
    CHECK(r.out.find("points: 61000") != std::string::npos);
    CHECK(r.out.find("converted from: p.ply p.csv") != std::string::npos);
    CHECK(temporaries(dir.path).empty());
}

TEST_CASE("convert -o pts.mlc: a --memory too small for one brick is exit 1, nothing written", "[cli][point_store]") {
    if (!have_shared_data()) return;
    TempDir dir("mlc-cli-mem");
    const auto r = sh("MESHLESS convert " + (shared_data() / "scattered" / "sparsePoints.txt").string() + " -o " +
                          (dir / "p.mlc").string() + " --memory 1M",
                      dir);
    CHECK(r.code == 1);
    CHECK(r.err.find("--memory") != std::string::npos);
    CHECK(r.err.find("too small") != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(dir / "p.mlc"));
    CHECK(temporaries(dir.path).empty());
}

TEST_CASE("a damaged point store: one line naming the file and the brick, exit 2, nothing written", "[cli][point_store]") {
    if (!have_shared_data()) return;
    TempDir dir("mlc-cli-bad");
    const std::string ply = (dir / "p.ply").string(), mlc = (dir / "p.mlc").string();
    REQUIRE(sh("MESHLESS sample " + bucky() + " --count 5000 -o " + ply, dir).code == 0);
    REQUIRE(sh("MESHLESS convert " + ply + " -o " + mlc + " --brick-points 128", dir).code == 0);
    std::string b = slurp(mlc);
    b[700] ^= 0x40;  // inside the first brick's frame
    spit(mlc, b);
    for (const std::string& cmd : {"verify " + mlc, "isosurface " + mlc + " --iso 100 -o " + (dir / "iso.ply").string(),
                                  "convert " + mlc + " -o " + (dir / "again.mlc").string(), "info " + mlc}) {
        INFO(cmd);
        const auto r = sh("MESHLESS " + cmd, dir);
        CHECK(r.code == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK(r.err.find(mlc + ": brick 0 (cell level") != std::string::npos);
        CHECK(r.err.find("checksum mismatch") != std::string::npos);
    }
    CHECK_FALSE(fs::exists(dir / "iso.ply"));
    CHECK_FALSE(fs::exists(dir / "again.mlc"));
    CHECK(temporaries(dir.path).empty());
    spit(mlc, b.substr(0, b.size() / 2));  // truncated
    const auto r = sh("MESHLESS verify " + mlc, dir);
    CHECK(r.code == 2);
    CHECK(r.err.find(mlc) != std::string::npos);
}

TEST_CASE("isosurface of a .mlc: the samples of the same points as PLY, in another order", "[cli][point_store]") {
    if (!have_shared_data()) return;
    TempDir dir("mlc-cli-iso");
    const std::string ply = (dir / "p.ply").string(), mlc = (dir / "p.mlc").string();
    REQUIRE(sh("MESHLESS sample " + bucky() + " --count 4000 -o " + ply, dir).code == 0);
    REQUIRE(sh("MESHLESS convert " + ply + " -o " + mlc + " --brick-points 64", dir).code == 0);
    const std::string a = (dir / "a.ply").string(), b = (dir / "b.ply").string();
    REQUIRE(sh("MESHLESS isosurface " + ply + " --iso 100 -j 1 -o " + a, dir).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + mlc + " --iso 100 -j 1 -o " + b, dir).code == 0);
    // The fields sort their points by Morton code internally (ties by input order), so the field
    // is the same; the samples are seeded point by point in input order, so their order differs.
    const std::string pa = slurp(a), pb = slurp(b);
    REQUIRE(pa.size() == pb.size());
    // x y z nx ny nz radius value as float32 (formats/ply_points.hpp)
    CHECK(sorted_records(pa, 32) == sorted_records(pb, 32));
}

/// 60,000 points uniform in the unit cube with a sphere-like value (0.3 at about the radius 0.3), as CSV.
std::string uniform_points_csv(std::uint64_t seed) {
    std::string csv = "x,y,z,value\n";
    std::uint64_t s = seed;
    const auto next = [&s] {  // (splitmix64: the same points on every machine)
        std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
    };
    char line[160];
    for (int i = 0; i < 60000; ++i) {
        const double x = next(), y = next(), z = next();
        const double v = std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) + (z - 0.45) * (z - 0.45)) + 0.05 * std::sin(9 * x);
        std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f,%.6f\n", x, y, z, v);
        csv += line;
    }
    return csv;
}

TEST_CASE("isosurface of a .mlc in slabs within --memory: the bytes of one slab for any budget and --threads", "[cli][point_store]") {
    TempDir dir("mlc-cli-slabs");
    const std::string csv = (dir / "u.csv").string(), mlc = (dir / "u.mlc").string();
    spit(csv, uniform_points_csv(7));
    REQUIRE(sh("MESHLESS convert " + csv + " -o " + mlc + " --brick-points 256", dir).code == 0);
    // (--max-travel 0.5: a slab's query box reaches half as far, so 60,000 points make several)
    const std::string common = " --iso 0.3 --max-travel 0.5 --stats -o ";
    const std::string one = (dir / "one.ply").string();
    auto r = sh("MESHLESS isosurface " + mlc + common + one + " --memory 2G -j 2", dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("point store in 1 slabs") != std::string::npos);
    const std::string want = slurp(one);
    REQUIRE(want.size() > 100000);
    CHECK(r.err.find("times over") == std::string::npos);
#ifdef MESHLESS_SANITIZED  // (each run takes ~45 s instrumented: two budgets, the in-memory runs in the main tier)
    const std::vector<const char*> budgets{"--memory 48M -j 1", "--memory 30M -j 2"};
#else
    const std::vector<const char*> budgets{"--memory 48M -j 1", "--memory 48M -j 2", "--memory 55M -j 2", "--memory 30M -j 2"};
#endif
    for (const char* opts : budgets) {
        INFO(opts);
        const std::string out = (dir / "slabs.ply").string();
        r = sh("MESHLESS isosurface " + mlc + common + out + " " + opts, dir);
        INFO(r.err);
        REQUIRE(r.code == 0);
        CHECK(r.err.find("point store in 1 slabs") == std::string::npos);
        CHECK(r.err.find(" slabs (") != std::string::npos);
        CHECK(slurp(out) == want);
        // a budget near the least that runs reads the points many times over: said
        if (std::string(opts).find("30M") != std::string::npos) CHECK(r.err.find("times over; more memory makes fewer") != std::string::npos);
    }
#ifndef MESHLESS_SANITIZED
    // the same points read into memory (a PLY): the same samples, in another order
    const std::string ply = (dir / "u.ply").string(), mem = (dir / "mem.ply").string();
    r = sh("MESHLESS isosurface " + csv + " --iso 0.3 --max-travel 0.5 -o " + mem + " -j 2 --memory 48M", dir);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("warning: --memory bounds only a point store (.mlc)") != std::string::npos);  // (held whole: said)
    CHECK(sorted_records(slurp(mem), 32) == sorted_records(want, 32));
    // no bound on Newton's travel: no slab bound either, the store is read whole (and --memory says so)
    r = sh("MESHLESS isosurface " + mlc + " --iso 0.3 --max-travel 0 --stats -o " + (dir / "whole.ply").string() + " --memory 48M", dir);
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(r.err.find("warning: --memory bounds only a point store") != std::string::npos);
    CHECK(r.err.find(" slabs (") == std::string::npos);
#endif
    // a budget below one layer: exit 1, one line saying how much would do, nothing written
    const std::string small = (dir / "small.ply").string();
    r = sh("MESHLESS isosurface " + mlc + common + small + " --memory 10M", dir);
    CHECK(r.code == 1);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.find("--memory 10 MiB is too small") != std::string::npos);
    CHECK(r.err.find("the fullest layer needs about --memory") != std::string::npos);
    CHECK_FALSE(fs::exists(small));
    CHECK(temporaries(dir.path).empty());
}

TEST_CASE("probe, slice, resample and render of a .mlc in slabs within --memory: the whole field's bytes for any budget and --threads",
          "[cli][point_store]") {
    TempDir dir("mlc-cli-queries");
    const std::string csv = (dir / "u.csv").string(), mlc = (dir / "u.mlc").string(), mlf = (dir / "u.mlf").string();
    spit(csv, uniform_points_csv(7));
    REQUIRE(sh("MESHLESS convert " + csv + " -o " + mlc + " --brick-points 256", dir).code == 0);
    // the oracle: the field fitted to the whole store in memory (fit), its support test over every point
    REQUIRE(sh("MESHLESS fit " + mlc + " -o " + mlf, dir).code == 0);
    std::string at = "x,y,z\n";  // positions in and beyond the unit cube, in no order
    for (int i = 0; i < 3000; ++i) {
        char line[96];
        std::snprintf(line, sizeof line, "%.5f,%.5f,%.5f\n", -0.1 + 1.2 * std::fmod(i * 0.6180339887, 1.0),
                      -0.1 + 1.2 * std::fmod(i * 0.7548776662, 1.0), -0.1 + 1.2 * std::fmod(i * 0.5698402910, 1.0));
        at += line;
    }
    spit((dir / "at.csv").string(), at);
    struct Query {
        const char* name;
        std::string args;
    };
#ifdef MESHLESS_SANITIZED  // (a grid and a picture: the main tier runs every query)
    const std::vector<Query> queries{{"ref.nrrd", "resample " + mlc + " --grid 24,20,28"},
                                     {"ref_render2.png", "render " + mlc + " --size 64x64 --azimuth 10 --elevation 80 --zoom 3"}};
#else
    const std::vector<Query> queries{{"ref.nrrd", "resample " + mlc + " --grid 24,20,28"},
                                     {"ref.csv", "probe " + mlc + " --at-file " + (dir / "at.csv").string()},
                                     {"ref.png", "slice " + mlc + " --plane y=0.4 --size 120x120 --colorbar"},
                                     {"ref_render.png", "render " + mlc + " --size 96x80 --shade --tf viridis"},
                                     {"ref_render2.png", "render " + mlc + " --size 64x64 --azimuth 10 --elevation 80 --zoom 3"}};
#endif
    for (const Query& q : queries) {
        INFO(q.args);
        const auto ext = fs::path(q.name).extension().string();
        auto r = sh("MESHLESS " + q.args + " --field " + mlf + " -o " + (dir / q.name).string(), dir);
        REQUIRE(r.code == 0);
        const std::string want = slurp((dir / q.name).string());
        REQUIRE(want.size() > 1000);
#ifdef MESHLESS_SANITIZED  // (the in-memory budget and one thread count: the main tier runs them all)
        const std::vector<const char*> budgets{"--memory 2G -j 2", "--memory 20M -j 2"};
#else
        const std::vector<const char*> budgets{"--memory 2G -j 2", "--memory 30M -j 1", "--memory 20M -j 2"};
#endif
        for (const char* opts : budgets) {
            INFO(opts);
            const std::string out = (dir / ("out" + ext)).string();
            r = sh("MESHLESS " + q.args + " --stats -o " + out + " " + opts, dir);
            INFO(r.err);
            REQUIRE(r.code == 0);
            CHECK(r.err.find(std::string(opts).find("2G") != std::string::npos ? "point store in 1 slabs" : " slabs (") != std::string::npos);
            CHECK(slurp(out) == want);
        }
        // a budget below one slab's field: exit 1, one line saying how much would do, nothing written
        const std::string small = (dir / ("small" + ext)).string();
        r = sh("MESHLESS " + q.args + " -o " + small + " --memory 4M", dir);
        CHECK(r.code == 1);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK(r.err.find("--memory 4 MiB is too small for this store") != std::string::npos);
        CHECK(r.err.find("it needs about --memory") != std::string::npos);
        CHECK_FALSE(fs::exists(small));
    }
    // another field kind holds the points whole, and --memory says so
    auto r = sh("MESHLESS resample " + mlc + " --grid 8,8,8 --field rbf-grid --memory 30M -o " + (dir / "rbf.nrrd").string(), dir);
    CHECK(r.code == 0);
    CHECK(r.err.find("warning: --memory bounds only a point store (.mlc) with the mpu field") != std::string::npos);
    CHECK(temporaries(dir.path).empty());
}

TEST_CASE("mpirun -np 2 and 3 isosurface of a .mlc: each rank its own layers, the single-process bytes", "[cli][point_store][mpi]") {
    TempDir dir("mlc-cli-mpi");
    const std::string mpirun = mpirun_prefix(dir);
    if (mpirun.empty()) {
        WARN("mpirun not installed: MPI test skipped");
        return;
    }
    const std::string csv = (dir / "u.csv").string(), mlc = (dir / "u.mlc").string();
    spit(csv, uniform_points_csv(7));
    REQUIRE(sh("MESHLESS convert " + csv + " -o " + mlc + " --brick-points 256", dir).code == 0);
    const std::string opts = " --max-travel 0.5 --threads 1 --size 96x96", common = " --iso 0.3" + opts;
    const std::string D = dir.path.string();
    REQUIRE(sh("MESHLESS isosurface " + mlc + common + " -o " + D + "/one.ply --png " + D + "/one.png", dir).code == 0);
    auto r = sh(mpirun + "MESHLESS isosurface " + mlc + common + " --stats --memory 64M -o " + D + "/two.ply --png " + D + "/two.png", dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("over 2 ranks, each its own stencil layers") != std::string::npos);
    CHECK(r.err.find("rank 1 at most") != std::string::npos);
    CHECK(slurp(dir / "one.ply").size() > 100000);
    CHECK(slurp(dir / "one.ply") == slurp(dir / "two.ply"));
    CHECK(slurp(dir / "one.png") == slurp(dir / "two.png"));
#ifndef MESHLESS_SANITIZED  // (instrumented, each run of these 60,000 points takes half a minute: the rank split and
                            // --dedup are checked by tests/stream/test_scattered_store_ranks.cpp there)
    // three ranks with --dedup on rank 0's side
    REQUIRE(sh("MESHLESS isosurface " + mlc + common + " --dedup 0.5 -o " + D + "/dd1.ply", dir).code == 0);
    r = sh(mpirun_prefix(dir, 3) + "MESHLESS isosurface " + mlc + common + " --dedup 0.5 -o " + D + "/dd3.ply", dir);
    REQUIRE(r.code == 0);
    CHECK(slurp(dir / "dd1.ply") == slurp(dir / "dd3.ply"));
#endif
    // an isovalue outside the data: the single process's empty output and warning, once
    REQUIRE(sh("MESHLESS isosurface " + mlc + opts + " --iso 50 -o " + D + "/e1.ply", dir).code == 0);
    r = sh(mpirun + "MESHLESS isosurface " + mlc + opts + " --iso 50 -o " + D + "/e2.ply", dir);
    CHECK(r.code == 0);
    CHECK(slurp(dir / "e1.ply") == slurp(dir / "e2.ply"));
    // a usage error: said once (rank 0), every rank exits 1 without an abort
    r = sh(mpirun + "MESHLESS isosurface " + mlc + common + " --field nope -o " + D + "/u.ply", dir);
    CHECK(r.code == 1);
    std::size_t said = 0;
    for (std::size_t at = r.err.find("--field: expected"); at != std::string::npos; at = r.err.find("--field: expected", at + 1)) ++said;
    CHECK(said == 1);
    CHECK(r.err.find("MPI_ABORT") == std::string::npos);
    // a budget too small on every rank fails the job, nothing written
    r = sh(mpirun + "MESHLESS isosurface " + mlc + common + " --memory 10M -o " + D + "/small.ply", dir);
    CHECK(r.code != 0);
    CHECK(r.err.find("too small") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "small.ply"));
    CHECK(temporaries(dir.path).empty());
}

TEST_CASE("convert -o pts.mlc killed mid-run: no temporaries (SIGKILL: swept by the next run)", "[cli][point_store][signals]") {
    if (!have_shared_data()) return;
    TempDir dir("mlc-cli-signals");
    const std::string ply = (dir / "p.ply").string();
    REQUIRE(sh("MESHLESS sample " + lidc2() + " --count 3000000 -o " + ply, dir).code == 0);
    fs::create_directories(dir / "out");
    const fs::path out = dir / "out" / "p.mlc";
    const std::vector<std::string> args = {"convert", ply, "-o", out.string(), "--memory", "24M", "-j", "1"};
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        INFO(strsignal(sig));
        const pid_t pid = spawn(args, dir);
        REQUIRE(wait_for_temporary(pid, out));  // the spool of the sorted runs
        ::kill(pid, sig);
        CHECK(wait_code(pid) == 128 + sig);
        INFO(slurp(dir / "stderr.txt"));
        CHECK(temporaries(dir / "out").empty());
        CHECK_FALSE(fs::exists(out));
    }
    const pid_t pid = spawn(args, dir);
    REQUIRE(wait_for_temporary(pid, out));
    ::kill(pid, SIGKILL);
    CHECK(wait_code(pid) == 128 + SIGKILL);
    CHECK_FALSE(temporaries(dir / "out").empty());  // nothing can clean up after SIGKILL ...
    const auto r = sh("MESHLESS convert " + ply + " -o " + out.string() + " --memory 24M", dir);
    CHECK(r.code == 0);
    CHECK(temporaries(dir / "out").empty());  // ... but the next run removes what it left
    CHECK(r.err.find("removed") != std::string::npos);
    CHECK(sh("MESHLESS verify " + out.string(), dir).code == 0);
}
