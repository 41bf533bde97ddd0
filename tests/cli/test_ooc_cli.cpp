// meshless convert / verify / synth end to end: quiet success, identical bytes across runs and
// thread counts, verify naming the bad brick, a full disk, a killed conversion, usage errors.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>

#include "cli_harness.hpp"
#include "formats/volume_reader.hpp"
#include "ooc/brick_store.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

std::string tooth() { return (shared_data() / "tooth" / "tooth_103x94x161_uint8.raw").string(); }
std::string lidc2() { return (shared_data() / "vtkjs_LIDC2" / "LIDC2.vti").string(); }

std::vector<std::string> files_in(const fs::path& d) {
    std::vector<std::string> r;
    for (const auto& e : fs::directory_iterator(d)) r.push_back(e.path().filename().string());
    std::sort(r.begin(), r.end());
    return r;
}

}  // namespace

TEST_CASE("meshless convert and verify: quiet, deterministic, verify names the bad brick", "[ooc][cli]") {
    if (!have_shared_data()) return;
    TempDir dir("ooc-cli");
    const std::string a = (dir / "a.mlb").string(), b = (dir / "b.mlb").string(), c = (dir / "c.mlb").string();
    auto r = sh("MESHLESS convert " + tooth() + " -o " + a, dir);
    REQUIRE(r.code == 0);
    CHECK(r.out.empty());
    CHECK(r.err.empty());
    REQUIRE(sh("MESHLESS convert " + tooth() + " -o " + b + " --threads 2", dir).code == 0);
    r = sh("MESHLESS convert " + tooth() + " -o " + c + " --threads 1 --stats", dir);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("MB/s") != std::string::npos);
    CHECK(r.err.find("ratio") != std::string::npos);
    CHECK(slurp(a) == slurp(b));
    CHECK(slurp(a) == slurp(c));

    r = sh("MESHLESS verify " + a, dir);
    CHECK(r.code == 0);
    CHECK(r.out == "ok: 60 bricks\n");
    // bricks beyond the memory budget are not read: a usage matter (raise --memory), not damage
    r = sh("MESHLESS verify " + a + " --memory 1K", dir);
    CHECK(r.code == 1);
    CHECK(r.err.find("more than the memory budget of 1024 bytes (--memory); not checked") != std::string::npos);
    r = sh("MESHLESS info " + a, dir);
    CHECK(r.code == 0);
    CHECK(r.out.find("brick store") != std::string::npos);
    CHECK(r.out.find("compression ratio") != std::string::npos);

    // Flip one bit in brick 17.
    const auto store = BrickStore::open(a);
    const auto& e = store->bricks()[17];
    std::string bytes = slurp(a);
    bytes[e.offset + 5] ^= 0x01;
    const std::string bad = (dir / "bad.mlb").string();
    spit(bad, bytes);
    r = sh("MESHLESS verify " + bad, dir);
    CHECK(r.code == 2);
    CHECK(r.err.find("brick 17 ") != std::string::npos);
    CHECK(r.err.find(voxel_range_string(store->box(17))) != std::string::npos);
    // Truncated.
    spit(bad, bytes.substr(0, bytes.size() / 2));
    r = sh("MESHLESS verify " + bad, dir);
    CHECK(r.code == 2);
    CHECK(r.err.find("truncated") != std::string::npos);

    // Several stores, a sample store among them: every one is checked and named, a bad one anywhere
    // in the list is exit 2 and the others are still reported.
    const std::string mls = (dir / "a.mls").string();
    REQUIRE(sh("MESHLESS generate " + a + " --all -o " + mls, dir).code == 0);
    r = sh("MESHLESS verify " + a + " " + mls, dir);
    CHECK(r.code == 0);
    CHECK(r.out.find(a + ": ok: 60 bricks\n") != std::string::npos);
    CHECK(r.out.find(mls + ": ok: ") != std::string::npos);
    CHECK(r.out.find(" buckets, ") != std::string::npos);
    r = sh("MESHLESS verify " + bad + " " + c + " " + mls, dir);
    CHECK(r.code == 2);
    CHECK(r.err.find("truncated") != std::string::npos);
    CHECK(r.out.find(c + ": ok: 60 bricks") != std::string::npos);
    CHECK(r.out.find(mls + ": ok: ") != std::string::npos);
    // a sample store with a damaged bucket: named, exit 2 (its header and table still read)
    std::string sb = slurp(mls);
    sb[600] ^= 0x40;  // inside the first bucket's keys (they start after the 512-byte header)
    const std::string badmls = (dir / "bad.mls").string();
    spit(badmls, sb);
    r = sh("MESHLESS verify " + badmls, dir);
    CHECK(r.code == 2);
    CHECK(r.err.find("bad.mls: bucket ") != std::string::npos);
}

TEST_CASE("meshless convert on a full disk: exit 2, clear message, no output, no temporaries", "[ooc][cli]") {
    if (!have_shared_data()) return;
    TempDir dir("ooc-cli-full");
    fs::create_directories(dir / "out");
    const std::string out = (dir / "out" / "t.mlb").string();
    // 64 blocks of 512 bytes: far less than the ~1 MB store.
    const auto r = sh("ulimit -f 64; trap \"\" XFSZ; MESHLESS convert " + tooth() + " -o " + out, dir);
    CHECK(r.code == 2);
    CHECK(r.err.find("t.mlb") != std::string::npos);
    CHECK(r.err.find("write failed") != std::string::npos);
    CHECK(files_in(dir / "out").empty());
}

TEST_CASE("meshless synth: upsampled LIDC2, and a conversion killed with SIGKILL", "[ooc][cli]") {
    if (!have_shared_data()) return;
    TempDir dir("ooc-cli-synth");
    const std::string ref = (dir / "ref.mlb").string(), out = (dir / "big.mlb").string();
    auto r = sh("MESHLESS synth --upsample 2 " + lidc2() + " -o " + ref, dir);
    REQUIRE(r.code == 0);
    CHECK(r.err.empty());
    const auto store = BrickStore::open(ref);
    CHECK(store->info().grid.dims == std::array<std::int64_t, 3>{511, 511, 265});
    CHECK(sh("MESHLESS verify " + ref, dir).code == 0);

    // Kill -9 while the spool is being written: no big.mlb appears.
    r = sh("MESHLESS synth --upsample 2 " + lidc2() + " -o " + out + " & pid=$!; "
           "for i in $(seq 1 2000); do ls " + dir.path.string() + "/big.mlb.tmp-*.spool >/dev/null 2>&1 && break; sleep 0.005; done; "
           "kill -9 $pid; wait $pid; exit 0", dir);
    CHECK(r.code == 0);
    CHECK_FALSE(fs::exists(out));
    // The rerun removes the dead run's temporaries and writes the same bytes as an uninterrupted run.
    REQUIRE(sh("MESHLESS synth --upsample 2 " + lidc2() + " -o " + out, dir).code == 0);
    CHECK(slurp(out) == slurp(ref));
    CHECK(files_in(dir.path) == std::vector<std::string>{"big.mlb", "ref.mlb", "stderr.txt", "stdout.txt"});
}

TEST_CASE("meshless convert/synth/verify usage errors", "[ooc][cli]") {
    TempDir dir("ooc-cli-usage");
    const std::string raw = (dir / "v_4x4x4_uint8.raw").string();
    spit(raw, std::string(64, '\x07'));
    CHECK(sh("MESHLESS convert " + raw + " -o " + (dir / "v.mlb").string(), dir).code == 0);
    CHECK(sh("MESHLESS verify " + (dir / "v.mlb").string(), dir).out == "ok: 1 bricks\n");
    CHECK(sh("MESHLESS convert " + raw, dir).code == 1);                                  // no -o
    CHECK(sh("MESHLESS convert " + raw + " -o -", dir).code == 1);                        // stdout
    CHECK(sh("MESHLESS convert " + raw + " -o x.mlb --brick 1", dir).code == 1);          // brick
    CHECK(sh("MESHLESS convert " + raw + " -o x.mlb --zstd-level 30", dir).code == 1);         // level
    CHECK(sh("MESHLESS synth " + raw + " -o x.mlb", dir).code == 1);                      // no --upsample
    CHECK(sh("MESHLESS synth --upsample 2 --method cubic " + raw + " -o x.mlb", dir).code == 1);
    CHECK(sh("MESHLESS verify", dir).code == 1);
    CHECK(sh("MESHLESS verify " + raw, dir).code == 2);                                   // not a store
    CHECK(sh("MESHLESS verify " + (dir / "missing.mlb").string(), dir).code == 2);
}
