// formats/temporary_files: the registry of live temporaries (what the signal handlers remove) and
// the sweep of stale temporaries of processes that no longer exist.
#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "formats/atomic_file.hpp"
#include "formats/temporary_files.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

void touch(const fs::path& p) { std::ofstream(p) << "x"; }

/// The pid of a child that has exited and been reaped: kill(pid, 0) fails with ESRCH.
pid_t dead_pid() {
    const pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return pid;
}

}  // namespace

TEST_CASE("temporary registry: register, remove_live_temporaries unlinks, unregister forgets", "[formats][temporary]") {
    TempDir dir("tmpreg");
    const std::size_t before = live_temporary_count();
    const fs::path a = dir / "a.tmp-1", b = dir / "b.tmp-1";
    touch(a);
    touch(b);
    {
        TemporaryRegistration ra(a.string());
        TemporaryRegistration rb(b.string());
        CHECK(live_temporary_count() == before + 2);
        rb.release();
        CHECK(live_temporary_count() == before + 1);
        remove_live_temporaries();
        CHECK_FALSE(fs::exists(a));
        CHECK(fs::exists(b));  // released: not ours any more
    }
    CHECK(live_temporary_count() == before);
    // too long a path is not registered (and says so)
    CHECK(register_temporary(std::string(kMaxTemporaryPath, 'x')) == -1);
    CHECK(register_temporary("") == -1);
    // the table is bounded: filling it fails cleanly, freeing a slot makes room again
    std::vector<int> slots;
    for (int s; (s = register_temporary((dir / "never").string())) >= 0;) slots.push_back(s);
    CHECK(slots.size() == kMaxLiveTemporaries - before);
    unregister_temporary(slots.back());
    CHECK(register_temporary((dir / "again").string()) == slots.back());
    for (int s : slots) unregister_temporary(s);
    CHECK(live_temporary_count() == before);
}

TEST_CASE("AtomicFile registers its temporary until commit or destruction", "[formats][temporary]") {
    TempDir dir("tmpreg-atomic");
    const std::size_t before = live_temporary_count();
    const std::string out = (dir / "out.bin").string();
    {
        AtomicFile f(out);
        f.write("abc");
        CHECK(live_temporary_count() == before + 1);
        // what a signal handler does: the temporary goes, the output never appears
        remove_live_temporaries();
        CHECK_FALSE(fs::exists(out + ".tmp-" + std::to_string(::getpid())));
    }
    CHECK(live_temporary_count() == before);
    {
        AtomicFile f(out);
        f.write("abc");
        f.commit();
        CHECK(live_temporary_count() == before);
        remove_live_temporaries();  // nothing registered: the committed output stays
    }
    CHECK(fs::exists(out));
}

TEST_CASE("AtomicFile: both durabilities replace the target only at commit, with the same bytes (and sync_to_disk)",
          "[formats][temporary]") {
    TempDir dir("tmpreg-durability");
    const std::string out = (dir / "out.bin").string();
    std::ofstream(out) << "old";
    std::string previous = "old";
    auto contents = [&] {
        std::ifstream in(out, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    for (Durability d : {Durability::replace, Durability::fsync}) {
        std::string big(std::size_t{9} << 20, 'x');  // past the 8 MiB write-back step of fsync mode
        big[12345] = d == Durability::fsync ? 'f' : 'r';
        {
            AtomicFile f(out, d);
            f.write(big);
            CHECK(contents() == previous);  // not in place before commit
            f.commit();
        }
        CHECK(contents() == big);
        std::size_t entries = 0;  // the old version (swapped out under the temporary's name) is gone
        for (const auto& e : fs::directory_iterator(dir.path)) entries += e.path().filename() == "out.bin" ? 0 : 1;
        CHECK(entries == 0);
        CHECK_NOTHROW(sync_to_disk(out));
        previous = big;
    }
    const std::string missing = (dir / "missing.ply").string();
    try {
        sync_to_disk(missing);
        FAIL("sync_to_disk of a missing file did not throw");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find(missing) != std::string::npos);
    }
}

TEST_CASE("remove_stale_temporaries: only NAME.tmp-PID[.spool] of processes that are gone", "[formats][temporary]") {
    TempDir dir("tmpreg-stale");
    const std::string out = (dir / "v.mlb").string();
    const std::string dead = std::to_string(dead_pid());
    const std::string self = std::to_string(::getpid()), parent = std::to_string(::getppid());
    const fs::path stale1 = out + ".tmp-" + dead, stale2 = out + ".tmp-" + dead + ".spool";
    const std::vector<fs::path> kept = {out + ".tmp-" + self, out + ".tmp-" + parent, out + ".tmp-" + parent + ".spool",
                                        out + ".tmp-" + dead + "x", out + ".tmp-", dir / ("w.mlb.tmp-" + dead),
                                        out + ".tmp-12345678901"};
    touch(stale1);
    touch(stale2);
    for (const auto& k : kept) touch(k);
    static std::vector<std::string> reported;
    reported.clear();
    set_stale_temporary_reporter([](const char* path, long) { reported.emplace_back(path); });
    auto removed = remove_stale_temporaries(out);
    set_stale_temporary_reporter(nullptr);
    std::sort(removed.begin(), removed.end());
    CHECK(removed == std::vector<std::string>{stale1.string(), stale2.string()});
    CHECK(reported.size() == 2);
    CHECK_FALSE(fs::exists(stale1));
    CHECK_FALSE(fs::exists(stale2));
    for (const auto& k : kept) CHECK(fs::exists(k));
    // AtomicFile sweeps before it writes
    touch(stale1);
    {
        AtomicFile f(out);
        f.write("x");
        f.commit();
    }
    CHECK_FALSE(fs::exists(stale1));
    // a missing folder is no error
    CHECK(remove_stale_temporaries((dir / "missing" / "x.ply").string()).empty());
}
