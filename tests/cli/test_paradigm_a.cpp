// Paradigm (A) from the command line (dissertation section 3.5, Table 3.1): a sample store made once,
// then `meshless extract vol.mls --iso V | meshless project | meshless write` gives the same points
// as `meshless isosurface VOLUME --iso V` (paradigm C), as a multiset (the store's order is
// bucket-major, not row-major); the SampleStoreSource batches respect the record cap; damaged or
// wrong inputs exit with code 2 and a message naming the file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "cli/cli_harness.hpp"
#include "formats/ply_points.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/cell_sampling.hpp"
#include "ooc/sample_store.hpp"
#include "stream/sample_store_source.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

/// A 40^3 uint8 torus (as tests/cli/test_cli_pipeline.cpp), written with the name convention.
Volume torus_u8(const TempDir& d, std::string& path) {
    const Volume f = make_analytic_volume(AnalyticField::torus, 40);
    GridSpec g;
    g.dims = {40, 40, 40};  // what the raw reader reports: origin 0, spacing 1
    Volume v(g, SampleType::u8);
    const float* src = reinterpret_cast<const float*>(f.bytes.data());
    for (std::size_t i = 0; i < v.bytes.size(); ++i)
        v.bytes[i] = static_cast<std::byte>(std::clamp(std::lround(src[i] * 200.0), 0L, 255L));
    path = (d / "torus_40x40x40_uint8.raw").string();
    spit(path, std::string(reinterpret_cast<const char*>(v.bytes.data()), v.bytes.size()));
    return v;
}

std::vector<std::array<unsigned char, 32>> point_multiset(const std::vector<PointRecord>& pts) {
    std::vector<std::array<unsigned char, 32>> out(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) std::memcpy(out[i].data(), &pts[i], 32);
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST_CASE("extract | project | write equals isosurface as a point multiset", "[parA]") {
    TempDir d("parA-cli");
    std::string vol;
    const Volume v = torus_u8(d, vol);
    const std::string D = d.path.string(), store = D + "/torus.mls";
    write_sample_store_from_volume(v.view(), store, vol);
    for (const char* iso : {"50.5", "50", "20.25", "120"}) {
        INFO("iso " << iso);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso " + iso + " -o " + D + "/c.ply", d).code == 0);
        const auto r = sh("MESHLESS extract " + store + " --iso " + iso + " --stats | MESHLESS project --threads 2 | MESHLESS write -o " +
                              D + "/a.ply",
                          d);
        REQUIRE(r.code == 0);
        CHECK_THAT(r.err, Catch::Contains("active"));
        REQUIRE(sh("MESHLESS extract " + store + " --iso " + iso + " --compress -o " + D + "/a.stream", d).code == 0);
        REQUIRE(sh("MESHLESS project " + D + "/a.stream | MESHLESS write -o " + D + "/b.ply", d).code == 0);
        const PlyPoints c = read_ply_points(D + "/c.ply"), a = read_ply_points(D + "/a.ply"), b = read_ply_points(D + "/b.ply");
        CHECK(c.points.size() > 100);
        CHECK(point_multiset(a.points) == point_multiset(c.points));
        CHECK(point_multiset(b.points) == point_multiset(c.points));
        // same source, iso, grid keys in the META. Framing keys aside: isosurface records the surface
        // bounds (bounds_lo/hi) and the volume's (volume_bounds_lo/hi); the sample store does not know
        // its active blocks yet, so extract still records the volume's bounds.
        auto without_bounds = [](std::vector<std::string> v) {
            std::erase_if(v, [](const std::string& s) { return s.find("bounds_") != std::string::npos; });
            return v;
        };
        CHECK(without_bounds(a.comments) == without_bounds(c.comments));
    }
    // the splatted picture path runs too
    CHECK(sh("MESHLESS extract " + store + " --iso 50.5 | MESHLESS project | MESHLESS splat -o " + D + "/a.png --size 64x64", d).code == 0);
    CHECK(std::filesystem::file_size(D + "/a.png") > 100);
}

TEST_CASE("extract refuses bad input with exit codes and messages naming the file", "[parA]") {
    TempDir d("parA-cli-bad");
    std::string vol;
    const Volume v = torus_u8(d, vol);
    const std::string D = d.path.string(), store = D + "/t.mls";
    write_sample_store_from_volume(v.view(), store, vol);
    auto r = sh("MESHLESS extract " + store + " > /dev/null", d);
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
    // a damaged bucket: the stream is left without its END frame, so project reports it truncated
    std::string bad = bytes;
    bad[kSampleStoreHeaderBytes + 100] ^= 0x20;
    spit(D + "/bad.mls", bad);
    const auto s = SampleStore::open(D + "/bad.mls");
    const double iso = s->buckets()[0].max_vmax;
    r = sh("MESHLESS extract " + D + "/bad.mls --iso " + std::to_string(iso) + " | MESHLESS project > /dev/null", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("bad.mls") && Catch::Contains("checksum"));
    r = sh("MESHLESS extract " + D + "/bad.mls --iso " + std::to_string(iso) + " -o " + D + "/out.stream", d);
    CHECK(r.code == 2);
    CHECK_FALSE(std::filesystem::exists(D + "/out.stream"));
}

TEST_CASE("SampleStoreSource yields capped batches equal to the query", "[parA]") {
    TempDir d("parA-source");
    GridSpec g;
    g.dims = {64, 64, 48};
    Volume v(g, SampleType::u8);
    std::mt19937 rng(3);
    for (auto& b : v.bytes) b = static_cast<std::byte>(rng() & 0xff);
    write_sample_store_from_volume(v.view(), (d / "r.mls").string(), "r");
    const auto store = SampleStore::open((d / "r.mls").string());
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
    // and it is paradigm (C)'s cell set
    std::vector<SampleRecord> c;
    SamplingStats st;
    sample_active_cells(v.view(), 127.5, 0, cell_row_count(g), {}, c, st);
    CHECK(c.size() == got.size());
}
