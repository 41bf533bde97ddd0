// Smoke test of `meshless bench` (--quick): it runs, exits 0 and prints its tables. Timings are
// never asserted (they depend on the machine and its load); the accuracy section's own PASS/FAIL
// targets are checked by the kernel tests with oracles, here only that the section reports them.
#include <catch2/catch.hpp>

#include "cli_harness.hpp"

using namespace meshless::test;

namespace {

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

}  // namespace

TEST_CASE("bench accuracy --quick prints the accuracy table", "[bench]") {
    TempDir dir("bench-acc");
    const std::string md = (dir / "results.md").string();
    const RunResult r = sh("MESHLESS bench accuracy --quick --data " + shared_data().string() + " --markdown " + md,
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = r.out;
    INFO(text);
    CHECK(contains(text, "Machine: "));
    CHECK(contains(text, "mean dist [vox]"));
    CHECK(contains(text, "coverage"));
    CHECK(contains(text, "sphere"));
    CHECK(contains(text, "marschner") == false);  // fields are printed by their short names
    CHECK(contains(text, "ml "));
    CHECK((contains(text, "PASS") || contains(text, "FAIL")));
    // the markdown copy holds the same table as a pipe table
    const std::string m = slurp(md);
    CHECK(contains(m, "| field | grid | projection |"));
    CHECK(contains(m, "| --- |"));
}

TEST_CASE("bench speed --quick prints the speed tables", "[bench]") {
    TempDir dir("bench-speed");
    const RunResult r = sh("MESHLESS bench speed --quick --data " + shared_data().string(), dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = r.out;
    INFO(text);
    CHECK(contains(text, "IS ms"));
    CHECK(contains(text, "MC ms"));
    CHECK(contains(text, "IS/MC"));
    CHECK(contains(text, "FE ms"));
    CHECK(contains(text, "IS/MC memory"));
    CHECK(contains(text, "generate ms"));
    if (have_shared_data()) CHECK(contains(text, "fuel"));
    else CHECK(contains(text, "analytic sphere"));
}

TEST_CASE("bench rejects unknown sections and bad options", "[bench]") {
    TempDir dir("bench-bad");
    CHECK(sh("MESHLESS bench nonsense > /dev/null", dir).code == 1);
    CHECK(sh("MESHLESS bench speed --reps 0 > /dev/null", dir).code == 1);
}

TEST_CASE("bench speed without the data folder falls back to analytic volumes", "[bench]") {
    TempDir dir("bench-nodata");
    const RunResult r =
        sh("MESHLESS bench speed --quick --reps 1 --isovalues 2 --data " + (dir / "no-such-dir").string(),
           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = r.out;
    CHECK(contains(text, "not found"));
    CHECK(contains(text, "analytic sphere"));
    CHECK(contains(text, "IS/MC"));
}

TEST_CASE("bench ooc --quick prints the out-of-core tables and removes its scratch folder", "[bench]") {
    TempDir dir("bench-ooc");
    const std::string md = (dir / "ooc.md").string();
    const std::filesystem::path scratch = dir / "scratch";
    std::filesystem::create_directories(scratch);
    const RunResult r = sh("MESHLESS bench ooc --quick --isovalues 2 --data " + shared_data().string() + " --scratch " +
                               scratch.string() + " --markdown " + md,
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = r.out;
    INFO(text);
    CHECK(contains(text, "Machine: "));
    CHECK(contains(text, "convert MB/s"));
    CHECK(contains(text, "throughput fresh"));
    CHECK(contains(text, "A query ms"));
    CHECK(contains(text, "C full ms"));
    CHECK(contains(text, "MC ms"));
    CHECK(contains(text, "--threads 2"));
    CHECK((contains(text, "PASS") || contains(text, "FAIL")));
    // paradigms A and C select the same cells, and 1 and 2 threads write the same bytes
    CHECK_FALSE(contains(text, " NO"));
    if (have_shared_data()) {
        CHECK(contains(text, "LIDC2 chest CT"));
        CHECK(contains(text, "tooth"));
    } else {
        CHECK(contains(text, "analytic gyroid"));
    }
    if (std::filesystem::exists("/usr/bin/time")) CHECK(contains(text, "max RSS"));
    else CHECK(contains(text, "/usr/bin/time not found"));
    CHECK(contains(slurp(md), "| iso | active % |"));
    // the scratch folder is removed (no --keep)
    CHECK(std::filesystem::is_empty(scratch));
}

TEST_CASE("bench ooc --quick without the data folder uses an analytic volume", "[bench]") {
    TempDir dir("bench-ooc-nodata");
    const RunResult r = sh("MESHLESS bench ooc --quick --isovalues 2 --data " + (dir / "no-such-dir").string() +
                               " --scratch " + dir.path.string() + " --keep",
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = r.out;
    INFO(text);
    CHECK(contains(text, "not found"));
    CHECK(contains(text, "analytic gyroid"));
    CHECK(contains(text, "A query ms"));
    CHECK_FALSE(contains(text, " NO"));
    // --keep leaves the stores in place
    bool kept = false;
    for (const auto& e : std::filesystem::directory_iterator(dir.path))
        if (e.path().filename().string().rfind("meshless-bench-ooc-", 0) == 0)
            kept = kept || std::filesystem::exists(e.path() / "lung.mlb");
    CHECK(kept);
}

TEST_CASE("bench ooc refuses a scratch folder that does not exist", "[bench]") {
    TempDir dir("bench-ooc-bad");
    const RunResult r = sh("MESHLESS bench ooc --quick --scratch " + (dir / "missing").string() + " > /dev/null", dir);
    CHECK(r.code == 1);
    CHECK(r.err.find("--scratch") != std::string::npos);
}

TEST_CASE("bench fields --quick prints the field accuracy, reproduction and speed tables", "[bench]") {
    TempDir dir("bench-fields");
    const std::string md = (dir / "fields.md").string();
    const RunResult r = sh("MESHLESS bench fields --quick --data " + shared_data().string() + " --markdown " + md,
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = r.out;
    INFO(text);
    CHECK(contains(text, "Machine: "));
    CHECK(contains(text, "Franke 3-D"));
    CHECK(contains(text, "Marschner-Lobb"));
    for (const char* f : {"rbf-grid", "mpu", "global-rbf"}) CHECK(contains(text, f));
    CHECK(contains(text, "RMS err"));
    CHECK(contains(text, "max rel err"));
    CHECK(contains(text, "1 thread s"));
    CHECK(contains(text, "eval Mpts/s"));
    // SciPy's reference runs when /usr/bin/python3 has scipy, else the section says why it is skipped
    CHECK((contains(text, "scipy MQ") || contains(text, "SciPy not installed")));
    if (have_shared_data()) {
        CHECK(contains(text, "bucky ball"));
        CHECK(contains(text, "21114"));
        CHECK(contains(text, "2688"));
        CHECK(contains(text, "16000"));
    } else {
        CHECK(contains(text, "Franke stand-in"));
    }
    CHECK((contains(text, "PASS") || contains(text, "FAIL")));
    CHECK_FALSE(contains(text, "build failed"));
    CHECK(contains(slurp(md), "| function | N | field |"));
}
