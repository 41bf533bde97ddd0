// Paradigm (A) from the command line (dissertation section 3.5, Table 3.1): a sample store made
// once from a brick store (`generate vol.mlb --all -o vol.mls`), then
// `extract vol.mls --iso V | project | write` writes the very bytes of
// `generate vol.mlb --iso V | project | write` and of `isosurface vol.mlb --iso V` (paradigm C),
// for both projections, and `isosurface vol.mls --iso V` runs paradigm (A) in one process with the
// same bytes; SampleStoreSource batches respect the record cap; bad inputs (raw volume for --all,
// missing/changed .mlb, truncated or damaged .mls) exit non-zero with a message naming the file
// and leave no output.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "cli/cli_harness.hpp"
#include "kernels/analytic_volumes.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/sample_store.hpp"
#include "ooc/sample_store_format.hpp"
#include "ooc/sample_store_writer.hpp"
#include "stream/sample_store_source.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

/// A 40^3 uint8 torus written with the raw name convention.
std::string torus_u8(const TempDir& d) {
    const Volume f = make_analytic_volume(AnalyticField::torus, 40);
    std::string bytes(static_cast<std::size_t>(40 * 40 * 40), '\0');
    const float* src = reinterpret_cast<const float*>(f.bytes.data());
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<char>(std::clamp(std::lround(src[i] * 200.0), 0L, 255L));
    const std::string path = (d / "torus_40x40x40_uint8.raw").string();
    spit(path, bytes);
    return path;
}

}  // namespace

TEST_CASE("extract | project | write writes the bytes of paradigm (C), and isosurface reads a .mls", "[parA]") {
    TempDir d("parA-cli");
    const std::string vol = torus_u8(d), D = d.path.string();
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/t.mlb --brick 8", d).code == 0);
    const auto all = sh("MESHLESS generate " + D + "/t.mlb --all -o " + D + "/t.mls --stats", d);
    REQUIRE(all.code == 0);
    CHECK_THAT(all.err, Catch::Contains("span-space buckets"));
    for (const char* iso : {"50.5", "50", "20.25", "120"}) {
        for (const char* proj : {"approx", "exact"}) {
            INFO("iso " << iso << ", " << proj);
            const std::string P = std::string(" --projection ") + proj;
            REQUIRE(sh("MESHLESS isosurface " + D + "/t.mlb --iso " + iso + P + " -o " + D + "/c.ply", d).code == 0);
            REQUIRE(sh("MESHLESS generate " + D + "/t.mlb --iso " + iso + " | MESHLESS project" + P + " | MESHLESS write -o " + D +
                           "/g.ply", d).code == 0);
            const auto r = sh("MESHLESS extract " + D + "/t.mls --iso " + iso + " --stats | MESHLESS project --threads 2" + P +
                                  " | MESHLESS write -o " + D + "/a.ply", d);
            REQUIRE(r.code == 0);
            CHECK_THAT(r.err, Catch::Contains("active samples"));
            REQUIRE(sh("MESHLESS isosurface " + D + "/t.mls --iso " + iso + P + " --threads 2 -o " + D + "/i.ply", d).code == 0);
            const std::string c = slurp(D + "/c.ply");
            CHECK(c.size() > 3000);
            CHECK(slurp(D + "/g.ply") == c);
            CHECK(slurp(D + "/a.ply") == c);
            CHECK(slurp(D + "/i.ply") == c);
        }
    }
    // the stream travels cell-indexed as generate's does (the checks above: the same bytes after project)
    REQUIRE(sh("MESHLESS extract " + D + "/t.mls --iso 50.5 -o " + D + "/x.stream", d).code == 0);
    const auto xi = sh("MESHLESS info " + D + "/x.stream", d);
    CHECK(xi.code == 0);
    CHECK_THAT(xi.out, Catch::Contains("cell-indexed frames") && !Catch::Contains("(0 cell-indexed"));
    // a compressed stream, and the picture path
    REQUIRE(sh("MESHLESS extract " + D + "/t.mls --iso 50.5 --compress -o " + D + "/a.stream", d).code == 0);
    REQUIRE(sh("MESHLESS project " + D + "/a.stream | MESHLESS write -o " + D + "/b.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/t.mlb --iso 50.5 -o " + D + "/c.ply", d).code == 0);
    CHECK(slurp(D + "/b.ply") == slurp(D + "/c.ply"));
    CHECK(sh("MESHLESS isosurface " + D + "/t.mls --iso 50.5 --png " + D + "/a.png --size 64x64", d).code == 0);
    CHECK(std::filesystem::file_size(D + "/a.png") > 100);
    const auto info = sh("MESHLESS info " + D + "/t.mls", d);
    CHECK(info.code == 0);
    CHECK_THAT(info.out, Catch::Contains("t.mlb") && Catch::Contains("version 2"));
    // a store that records its volume's patient axes: paradigm (A) records them as (C) does (the
    // points' PLY comments, so splat faces alike), the same bytes
    if (!have_shared_data()) return;
    const std::string head = (shared_data() / "vtk_headsq" / "quarter.nhdr").string();
    REQUIRE(sh("MESHLESS convert " + head + " -o " + D + "/h.mlb", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + D + "/h.mlb --all -o " + D + "/h.mls", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/h.mlb --iso 1000.5 -o " + D + "/hc.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/h.mls --iso 1000.5 -o " + D + "/ha.ply", d).code == 0);
    REQUIRE(sh("MESHLESS extract " + D + "/h.mls --iso 1000.5 | MESHLESS project | MESHLESS write -o " + D + "/hp.ply", d).code == 0);
    const std::string hc = slurp(D + "/hc.ply");
    CHECK(hc.find("comment patient_axes ") != std::string::npos);
    CHECK(slurp(D + "/ha.ply") == hc);
    CHECK(slurp(D + "/hp.ply") == hc);
    // and the picture: the .mls's --png faces as the .mlb's (head up), as splat of its PLY
    REQUIRE(sh("MESHLESS isosurface " + D + "/h.mlb --iso 1000.5 --png " + D + "/hc.png --size 48x48", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/h.mls --iso 1000.5 --png " + D + "/ha.png --size 48x48", d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "/ha.ply -o " + D + "/hs.png --size 48x48", d).code == 0);
    CHECK(slurp(D + "/ha.png") == slurp(D + "/hc.png"));
    CHECK(slurp(D + "/hs.png") == slurp(D + "/hc.png"));
}

TEST_CASE("paradigm (A) commands refuse bad input with exit codes and messages naming the file", "[parA]") {
    TempDir d("parA-cli-bad");
    const std::string vol = torus_u8(d), D = d.path.string(), store = D + "/t.mls";
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/t.mlb --brick 8", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + D + "/t.mlb --all -o " + store, d).code == 0);
    auto r = sh("MESHLESS generate " + vol + " --all -o " + D + "/raw.mls", d);
    CHECK(r.code == 1);  // --all needs a brick store
    CHECK_THAT(r.err, Catch::Contains("convert"));
    CHECK_FALSE(std::filesystem::exists(D + "/raw.mls"));
    r = sh("MESHLESS extract " + store + " > /dev/null", d);
    CHECK(r.code == 1);  // no --iso
    r = sh("MESHLESS extract " + D + "/missing.mls --iso 3 > /dev/null", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("missing.mls"));
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 -o " + D + "/s.stream", d).code == 0);
    r = sh("MESHLESS extract " + D + "/s.stream --iso 50.5 > /dev/null", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("point stream"));
    const std::string bytes = slurp(store);
    spit(D + "/trunc.mls", bytes.substr(0, bytes.size() - 7));
    r = sh("MESHLESS extract " + D + "/trunc.mls --iso 50.5 > /dev/null", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("trunc.mls") && Catch::Contains("truncated"));
    std::string other = bytes;
    other[8] = 1;
    spit(D + "/v1.mls", other);
    r = sh("MESHLESS isosurface " + D + "/v1.mls --iso 50.5 -o " + D + "/o.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("v1.mls") && Catch::Contains("version 1"));
    // a damaged bucket: refused before any output, nothing left behind
    std::string bad = bytes;
    bad[kSampleStoreHeaderBytes + 2] ^= 0x20;
    spit(D + "/bad.mls", bad);
    const auto s = SampleStore::open(D + "/bad.mls");
    const std::string iso = std::to_string(s->info().value_lo + s->buckets()[0].a + 0.5);
    r = sh("MESHLESS extract " + D + "/bad.mls --iso " + iso + " -o " + D + "/out.stream", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("bad.mls") && Catch::Contains("checksum"));
    CHECK_FALSE(std::filesystem::exists(D + "/out.stream"));
    r = sh("MESHLESS isosurface " + D + "/bad.mls --iso " + iso + " -o " + D + "/out.ply", d);
    CHECK(r.code == 2);
    CHECK_FALSE(std::filesystem::exists(D + "/out.ply"));
    // the .mlb moved away, then changed
    std::filesystem::rename(D + "/t.mlb", D + "/u.mlb");
    r = sh("MESHLESS extract " + store + " --iso 50.5 -o " + D + "/out.stream", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("t.mls") && Catch::Contains("t.mlb") && Catch::Contains("missing"));
    CHECK_FALSE(std::filesystem::exists(D + "/out.stream"));
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/t.mlb --brick 16", d).code == 0);
    r = sh("MESHLESS isosurface " + store + " --iso 50.5 -o " + D + "/out.ply", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("t.mls") && Catch::Contains("changed"));
    CHECK_FALSE(std::filesystem::exists(D + "/out.ply"));
}

TEST_CASE("SampleStoreSource yields capped batches equal to the query", "[parA]") {
    TempDir d("parA-source");
    GridSpec g;
    g.dims = {64, 64, 48};
    Volume v(g, SampleType::u8);
    std::mt19937 rng(3);
    for (auto& b : v.bytes) b = static_cast<std::byte>(rng() & 0xff);
    const std::string mlb = (d / "r.mlb").string(), mls = (d / "r.mls").string();
    spit(d / "r_64x64x48_uint8.raw", std::string(reinterpret_cast<const char*>(v.bytes.data()), v.bytes.size()));
    REQUIRE(sh("MESHLESS convert " + (d / "r_64x64x48_uint8.raw").string() + " -o " + mlb + " --brick 64", d).code == 0);
    write_sample_store(*BrickStore::open(mlb), mls);
    const auto store = SampleStore::open(mls);
    std::vector<SampleRecord> expect;
    store->query(127.5, [&](std::span<const SampleRecord> b) { expect.insert(expect.end(), b.begin(), b.end()); });
    REQUIRE(expect.size() > 2 * kMaxBatchRecords);
    SampleStoreSource src(*store, 127.5);
    std::vector<SampleRecord> got;
    std::uint64_t seq = 0;
    while (auto b = src.next()) {
        CHECK(b->seq == seq++);
        CHECK(b->kind == RecordKind::sample);
        CHECK(b->samples.size() <= kMaxBatchRecords);
        got.insert(got.end(), b->samples.begin(), b->samples.end());
    }
    REQUIRE(got.size() == expect.size());
    CHECK(std::memcmp(got.data(), expect.data(), got.size() * sizeof(SampleRecord)) == 0);
    std::vector<SampleRecord> c;
    SamplingStats st;
    sample_active_cells(v.view(), 127.5, 0, cell_row_count(g), {}, c, st);
    CHECK(c.size() == got.size());
}
