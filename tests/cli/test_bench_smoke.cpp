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
    const std::string out = (dir / "out.txt").string();
    const std::string md = (dir / "results.md").string();
    const RunResult r = sh("MESHLESS bench accuracy --quick --data " + shared_data().string() + " --markdown " + md +
                               " > " + out,
                           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = slurp(out);
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
    const std::string out = (dir / "out.txt").string();
    const RunResult r = sh("MESHLESS bench speed --quick --data " + shared_data().string() + " > " + out, dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = slurp(out);
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
    const std::string out = (dir / "out.txt").string();
    const RunResult r =
        sh("MESHLESS bench speed --quick --reps 1 --isovalues 2 --data " + (dir / "no-such-dir").string() + " > " + out,
           dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string text = slurp(out);
    CHECK(contains(text, "not found"));
    CHECK(contains(text, "analytic sphere"));
    CHECK(contains(text, "IS/MC"));
}
