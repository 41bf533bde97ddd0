// Signals and write errors (faults): on SIGINT, SIGTERM, SIGHUP and SIGXFSZ meshless
// removes the temporaries it is writing and exits with 128 + signal; the next run removes stale
// temporaries of processes that are gone and says so; a write error on standard output (a full
// device) is an error, not exit 0; SIGBUS from a mapped input that shrinks is a one-line data error
// (exit 2), its temporaries removed too.
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "cli/signals.hpp"
#include "cli_harness.hpp"
#include "formats/atomic_file.hpp"
#include "formats/volume_reader.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

std::string lidc2() { return (shared_data() / "vtkjs_LIDC2" / "LIDC2.vti").string(); }

/// Starts meshless ARGS in dir with stdout/stderr to files, default signal dispositions and an
/// unblocked mask; fsize_limit > 0 sets RLIMIT_FSIZE (bytes) in the child, as `ulimit -f` does;
/// stdin_fd >= 0 becomes the child's standard input.
pid_t spawn(const std::vector<std::string>& args, const TempDir& dir, rlim_t fsize_limit = 0, int stdin_fd = -1) {
    std::vector<std::string> all = {meshless_exe()};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (::chdir(dir.path.c_str()) != 0) ::_exit(120);
        const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (o < 0 || e < 0) ::_exit(121);
        ::dup2(o, 1);
        ::dup2(e, 2);
        if (stdin_fd >= 0) ::dup2(stdin_fd, 0);
        for (int s : {SIGINT, SIGTERM, SIGHUP, SIGXFSZ}) ::signal(s, SIG_DFL);
        sigset_t none;
        sigemptyset(&none);
        ::sigprocmask(SIG_SETMASK, &none, nullptr);
        if (fsize_limit > 0) {
            const rlimit lim{fsize_limit, fsize_limit};
            ::setrlimit(RLIMIT_FSIZE, &lim);
        }
        ::execv(argv[0], argv.data());
        ::_exit(122);
    }
    return pid;
}

/// Exit status as a shell reports it: the code, or 128 + signal (then also `signalled`).
struct Exit {
    int code = -1;
    bool signalled = false;
};
Exit wait_for(pid_t pid) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(status)) return {128 + WTERMSIG(status), true};
    return {WEXITSTATUS(status), false};
}

/// Names in dir containing ".tmp-".
std::vector<std::string> temporaries(const fs::path& dir) {
    std::vector<std::string> r;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos) r.push_back(e.path().filename().string());
    return r;
}

/// Waits (up to 5 minutes) until a temporary of `out` exists, or the process has exited (false).
bool wait_for_temporary(pid_t pid, const fs::path& out) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
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

struct Case {
    const char* name;
    std::vector<std::string> args;  ///< "OUT" is replaced by the output path
    const char* output;
};

}  // namespace

TEST_CASE("SIGINT/SIGTERM/SIGHUP mid-run: exit 128+signal, no temporaries, no output", "[cli][signals]") {
    if (!have_shared_data()) return;
    TempDir dir("signals");
    // LIDC2 upsampled twice (511 x 511 x 265), long enough to be caught while writing; under the
    // sanitizers (5-10x slower) LIDC2 itself is as long and keeps the suite's time reasonable
#ifdef MESHLESS_SANITIZED
    const std::string upsample = "1";
#else
    const std::string upsample = "2";
#endif
    const std::string big = (dir / "big.mlb").string(), mls = (dir / "big.mls").string();
    REQUIRE(sh("MESHLESS synth --upsample " + upsample + " " + lidc2() + " -o " + big, dir).code == 0);
    REQUIRE(sh("MESHLESS generate --all " + big + " -o " + mls, dir).code == 0);
    fs::create_directories(dir / "out");
    const std::vector<Case> cases = {
        {"isosurface", {"isosurface", big, "--iso", "100.5", "-j", "1", "-o", "OUT"}, "iso.ply"},
        {"convert", {"convert", big, "-j", "1", "-o", "OUT"}, "c.mlb"},
        {"generate --all", {"generate", "--all", big, "-j", "1", "-o", "OUT"}, "g.mls"},
        {"extract", {"extract", mls, "--iso", "100.5", "-o", "OUT"}, "e.bin"},
    };
    for (const auto& c : cases)
        for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
            {
                INFO(c.name << ", " << strsignal(sig));
                const fs::path out = dir / "out" / c.output;
                auto args = c.args;
                for (auto& a : args)
                    if (a == "OUT") a = out.string();
                const pid_t pid = spawn(args, dir);
                REQUIRE(wait_for_temporary(pid, out));
                ::kill(pid, sig);
                const Exit e = wait_for(pid);
                INFO(slurp(dir / "stderr.txt"));
                CHECK(e.code == 128 + sig);
                CHECK_FALSE(e.signalled);  // exited by itself, after cleaning up
                CHECK(temporaries(dir / "out").empty());
                CHECK_FALSE(fs::exists(out));
            }
        }
}

TEST_CASE("every command interrupted mid-run by SIGINT, SIGTERM or SIGHUP exits 128+signal, leaving no temporaries", "[cli][signals]") {
    if (!have_shared_data()) return;
    TempDir dir("signals-every");
    // inputs that keep each command busy for seconds here (and longer under the sanitizers); the
    // stream readers wait on a standard input that never ends, so they are always mid-run
    const std::string big = (dir / "big.mlb").string(), pts = (dir / "pts.csv").string();
    REQUIRE(sh("MESHLESS synth --upsample 2 " + lidc2() + " -o " + big, dir).code == 0);
    REQUIRE(sh("MESHLESS sample " + big + " --count 200000 --seed 1 -o " + pts, dir).code == 0);
    // a cluster tree of fewer points, whose certified level of detail (a field fitted and checked
    // at every sample, per step of a bisection) takes seconds
    const std::string few = (dir / "few.csv").string(), tree = (dir / "few.mlh").string();
    REQUIRE(sh("MESHLESS sample " + big + " --count 20000 --seed 2 -o " + few, dir).code == 0);
    REQUIRE(sh("MESHLESS hierarchy " + few + " -o " + tree, dir).code == 0);
    fs::create_directories(dir / "out");
    std::vector<std::string> verify_args = {"verify"};
    verify_args.insert(verify_args.end(), 64, big);
    struct Timed {
        const char* name;
        std::vector<std::string> args;  ///< "OUT" is replaced by dir/out/<output>
        const char* output;
        bool from_stdin = false;        ///< reads a stream or a volume from a standard input left open
    };
    const std::vector<Timed> cases = {
        {"mc", {"mc", big, "--iso", "20.5", "-j", "1", "-o", "OUT"}, "m.ply"},  // (0.9 s alone; 100.5: 0.3 s)
        {"render", {"render", big, "--size", "2048x2048", "-j", "1", "-o", "OUT"}, "r.png"},
        {"synth", {"synth", "--upsample", "3", lidc2(), "-o", "OUT"}, "s.mlb"},
        {"sample", {"sample", big, "--count", "30000000", "-o", "OUT"}, "p.csv"},
        {"split", {"split", big, "--layout", "overlapping", "--blocks", "8", "-o", "OUT"}, "b.vtm"},
        {"fit", {"fit", pts, "-j", "1", "-o", "OUT"}, "f.mlf"},
        {"slice", {"slice", pts, "--plane", "z=0", "--size", "4096x4096", "-j", "1", "-o", "OUT"}, "s.png"},
        {"resample", {"resample", pts, "--grid", "256,256,256", "-j", "1", "-o", "OUT"}, "v.nrrd"},
        {"probe", {"probe", pts, "--at-file", pts, "-j", "1", "-o", "OUT"}, "p.csv"},
        {"hierarchy", {"hierarchy", lidc2(), "-j", "1", "-o", "OUT"}, "h.mlh"},
        {"demo", {"demo", "--size", "8192x8192", "-o", "OUT"}, "demo_out"},
        {"generate", {"generate", "-", "--iso", "100.5", "-o", "OUT"}, "g.bin", true},  // spooling its volume
        {"project", {"project", "-", "-o", "OUT"}, "p.bin", true},
        {"write", {"write", "-", "-o", "OUT"}, "w.ply", true},
        {"splat", {"splat", "-", "-o", "OUT"}, "s.png", true},
        {"info", {"info", "-"}, "none", true},
        {"verify", verify_args, "none"},  // every brick of each, decompressed: 64 x 0.04 s
        {"lod", {"lod", tree, "--max-error", "0", "--samples", few, "-j", "1", "-o", "OUT"}, "l.ply"},
    };
    for (const auto& c : cases)
        for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
            INFO(c.name << ", " << strsignal(sig));
            const fs::path out = dir / "out" / c.output;
            auto args = c.args;
            for (auto& a : args)
                if (a == "OUT") a = out.string();
            int in[2] = {-1, -1};
            if (c.from_stdin) REQUIRE(::pipe(in) == 0);
            const pid_t pid = spawn(args, dir, 0, in[0]);
            if (in[0] >= 0) ::close(in[0]);
            // past start-up (the handlers are installed first thing), well before the end
            std::this_thread::sleep_for(std::chrono::milliseconds(300));
            int status = 0;
            const bool running = ::waitpid(pid, &status, WNOHANG) == 0;
            INFO(slurp(dir / "stderr.txt"));
            REQUIRE(running);
            ::kill(pid, sig);
            const Exit e = wait_for(pid);
            if (in[1] >= 0) ::close(in[1]);
            INFO(slurp(dir / "stderr.txt"));
            CHECK(e.code == 128 + sig);
            CHECK_FALSE(e.signalled);  // exited by itself, after cleaning up
            CHECK(temporaries(dir / "out").empty());
            if (fs::is_directory(out))  // demo's output folder: made first, the files not written
                CHECK(fs::is_empty(out));
            else
                CHECK_FALSE(fs::exists(out));
        }
}

TEST_CASE("SIGXFSZ (ulimit -f): exit 153 and no temporaries, an ignored SIGXFSZ is a write error", "[cli][signals]") {
    if (!have_shared_data()) return;
    TempDir dir("signals-xfsz");
    const std::string tooth = (shared_data() / "tooth" / "tooth_103x94x161_uint8.raw").string();
    fs::create_directories(dir / "out");
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"convert", tooth, "-o", (dir / "out" / "t.mlb").string()},
             {"isosurface", tooth, "--iso", "100.5", "-o", (dir / "out" / "t.ply").string()}}) {
        const pid_t pid = spawn(args, dir, 64 * 1024);
        const Exit e = wait_for(pid);
        INFO(args[0] << ": " << slurp(dir / "stderr.txt"));
        CHECK(e.code == 128 + SIGXFSZ);
        CHECK_FALSE(e.signalled);
        CHECK(temporaries(dir / "out").empty());
        CHECK(fs::is_empty(dir / "out"));
        // one line that says why and names the output (not its temporary)
        const std::string err = slurp(dir / "stderr.txt");
        CHECK_THAT(err, Catch::Contains("meshless: file size limit exceeded (SIGXFSZ, ulimit -f) while writing '" + args.back() +
                                        "'; not written, temporaries removed\n"));
        CHECK(err.find(".tmp-") == std::string::npos);
    }
    // SIGXFSZ ignored (as batch runs use it): EFBIG is reported as a write error, exit 2
    const auto r = sh("ulimit -f 64; trap \"\" XFSZ; MESHLESS isosurface " + tooth + " --iso 100.5 -o " +
                          (dir / "out" / "t.ply").string(), dir);
    CHECK(r.code == 2);
    CHECK(r.err.find("t.ply") != std::string::npos);
    CHECK(fs::is_empty(dir / "out"));
}

TEST_CASE("a stale temporary of a dead process is removed at the next run, and said so", "[cli][signals]") {
    if (!have_shared_data()) return;
    TempDir dir("signals-stale");
    const std::string fuel = (shared_data() / "fuel" / "fuel_64x64x64_uint8.raw").string();
    const pid_t dead = ::fork();
    if (dead == 0) ::_exit(0);
    wait_for(dead);
    const fs::path out = dir / "f.ply";
    const fs::path stale = out.string() + ".tmp-" + std::to_string(dead);
    const fs::path live = out.string() + ".tmp-" + std::to_string(::getpid());  // this test: alive
    spit(stale, "half a file");
    spit(live, "someone else's");
    const auto r = sh("MESHLESS isosurface " + fuel + " --iso 20.5 -o " + out.string(), dir);
    CHECK(r.code == 0);
    CHECK_FALSE(fs::exists(stale));
    CHECK(fs::exists(live));
    CHECK(fs::exists(out));
    CHECK(r.err.find("removed stale temporary file") != std::string::npos);
    CHECK(r.err.find(stale.filename().string()) != std::string::npos);
    // a killed run's temporaries are stale for the next one: SIGKILL leaves them, the rerun removes them
#ifdef MESHLESS_SANITIZED
    const std::string big = lidc2();  // the sanitizers make it as slow as the upsampled one
#else
    const std::string big = (dir / "big.mlb").string();
    REQUIRE(sh("MESHLESS synth --upsample 2 " + lidc2() + " -o " + big, dir).code == 0);
#endif
    const fs::path c = dir / "c.mlb";
    const pid_t pid = spawn({"convert", big, "-j", "1", "-o", c.string()}, dir);
    REQUIRE(wait_for_temporary(pid, c));
    ::kill(pid, SIGKILL);
    CHECK(wait_for(pid).code == 128 + SIGKILL);
    const auto rerun = sh("MESHLESS convert " + big + " -o " + c.string(), dir);
    CHECK(rerun.code == 0);
    CHECK(rerun.err.find("removed stale temporary file") != std::string::npos);
    CHECK(temporaries(dir.path) == std::vector<std::string>{live.filename().string()});
    fs::remove(live);
}

TEST_CASE("info, verify and --help on a full device (/dev/full): exit 2 with a message", "[cli][signals]") {
    if (!fs::exists("/dev/full")) return;
    TempDir dir("full-device");
    const std::string raw = (dir / "v_4x4x4_uint8.raw").string();
    spit(raw, std::string(64, '\x07'));
    const std::string mlb = (dir / "v.mlb").string();
    REQUIRE(sh("MESHLESS convert " + raw + " -o " + mlb, dir).code == 0);
    for (const std::string& cmd : std::vector<std::string>{"MESHLESS info " + raw, "MESHLESS verify " + mlb, "MESHLESS --help",
                                  "MESHLESS info --help", "MESHLESS --version", "MESHLESS isosurface --help"}) {
        INFO(cmd);
        REQUIRE(sh(cmd, dir).code == 0);  // fine on a real stdout
        const auto r = sh(cmd + " >/dev/full", dir);
        CHECK(r.code == 2);
        // "(No space left on device)", or "(write error)" when the command flushed by itself
        CHECK(r.err.find("cannot write standard output (") != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
    // a reader that has gone stays a quiet success
    const auto r = sh("MESHLESS --help | head -c 1 >/dev/null", dir);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
}

TEST_CASE("batch killed mid-run: exit 128+signal, no temporaries, the rerun finishes what is left", "[cli][signals]") {
    TempDir dir("signals-batch");
    fs::create_directories(dir / "archive");
    // two volumes, so that the run is caught converting or extracting one of them
    for (const char* name : {"a", "b"}) {
        const std::string v = write_uint8_analytic_volume(dir, name, AnalyticField::torus, 192, 200.0, 0.0);
        fs::rename(v, dir / "archive" / fs::path(v).filename());
    }
    const fs::path out = dir / "nightly";
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        INFO(strsignal(sig));
        fs::remove_all(out);
        const pid_t pid = spawn({"batch", (dir / "archive").string(), "-o", out.string(), "--iso", "50.5", "-j", "1"}, dir);
        // wait for the first temporary anywhere in the output folder
        bool caught = false;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
        while (!caught && std::chrono::steady_clock::now() < deadline) {
            std::error_code ec;
            if (fs::is_directory(out, ec))
                for (const auto& e : fs::directory_iterator(out, ec))
                    caught = caught || e.path().filename().string().find(".tmp-" + std::to_string(pid)) != std::string::npos;
            int status = 0;
            if (!caught && ::waitpid(pid, &status, WNOHANG) == pid) break;
            if (!caught) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        REQUIRE(caught);
        ::kill(pid, sig);
        const Exit e = wait_for(pid);
        INFO(slurp(dir / "stderr.txt"));
        CHECK(e.code == 128 + sig);
        CHECK_FALSE(e.signalled);
        CHECK(temporaries(out).empty());
    }
    // the rerun completes; a third run finds everything up to date
    const auto r = sh("MESHLESS batch " + (dir / "archive").string() + " -o " + out.string() + " --iso 50.5", dir);
    INFO(r.err << r.out);
    CHECK(r.code == 0);
    CHECK(fs::exists(out / "a_192x192x192_uint8.mlb"));
    CHECK(fs::exists(out / "b_192x192x192_uint8_iso50.5.ply"));
    CHECK(temporaries(out).empty());
    const auto again = sh("MESHLESS batch " + (dir / "archive").string() + " -o " + out.string() + " --iso 50.5", dir);
    CHECK(again.code == 0);
    CHECK(again.out.find("0 done, 2 up to date") != std::string::npos);
}

TEST_CASE("SIGBUS: a volume read in place that shrinks while it is read gives one line and exit 2 and leaves no temporaries",
          "[cli][signals]") {
    TempDir d("sigbus");
    // a raw volume read in place (map_volume, as isosurface and render map a volume read whole)
    const fs::path in = d / "vol_128x128x64_uint8.raw", out = d / "out.ply", err = d / "stderr.txt";
    spit(in, std::string(std::size_t{1} << 20, 'v'));
    const pid_t pid = ::fork();
    if (pid == 0) {  // the child is meshless: the CLI's handlers, an output being written, a mapped input
        const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (e < 0) ::_exit(121);
        ::dup2(e, 2);
        meshless::cli::install_signal_cleanup();
        AtomicFile o(out.string());
        o.write("ply\n");
        std::fflush(o.handle());
        const Volume v = map_volume(in.string());
        if (v.bytes.size() != (std::size_t{1} << 20)) ::_exit(123);
        if (::truncate(in.c_str(), 0) != 0) ::_exit(122);
        volatile unsigned sum = 0;
        for (std::size_t i = 0; i < v.bytes.size(); i += 4096) sum = sum + static_cast<unsigned>(v.bytes[i]);  // SIGBUS
        ::_exit(99);
    }
    REQUIRE(pid > 0);
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 2);
    CHECK_THAT(slurp(err), Catch::Contains("an input file shrank or became unreadable while it was read (SIGBUS)"));
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(d.path)) left.push_back(e.path().filename().string());
    std::sort(left.begin(), left.end());
    CHECK(left == std::vector<std::string>{"stderr.txt", "vol_128x128x64_uint8.raw"});
}
