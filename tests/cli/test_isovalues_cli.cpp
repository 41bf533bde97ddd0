// Several isovalues in one run (`isosurface VOLUME --iso V1,V2,...`): the outputs hold the points of
// one run per value, concatenated in the order given (the oracle: the single runs' PLY bodies), from
// a volume, a brick store and a sample store alike; the header records the isovalues; the picture
// colours each surface and equals `splat` of the PLY; the inputs that take one isovalue a run say so.
// `mc --iso V1,V2,...`: one mesh holding the single runs' meshes in order, none welded to another.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>

#include "cli/cli_harness.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/point_stream.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {
/// The bytes after a PLY's header.
std::string ply_body(const std::filesystem::path& p) {
    const std::string b = slurp(p);
    const std::size_t at = b.find("end_header\n");
    REQUIRE(at != std::string::npos);
    return b.substr(at + 11);
}
std::string ply_header(const std::filesystem::path& p) {
    const std::string b = slurp(p);
    return b.substr(0, b.find("end_header\n"));
}
std::size_t count_of(const std::string& s, const std::string& needle) {
    std::size_t n = 0;
    for (std::size_t at = s.find(needle); at != std::string::npos; at = s.find(needle, at + 1)) ++n;
    return n;
}
}  // namespace

TEST_CASE("isosurface --iso V1,V2: one run per value concatenated, from a volume and both stores", "[cli][isovalues]") {
    TempDir d("isovalues");
    const std::string D = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "vol", AnalyticField::torus, 24, 200.0, 0.0);
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "v.mlb --brick 8", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + D + "v.mlb --all -o " + D + "v.mls", d).code == 0);
    for (const std::string& in : {vol, D + "v.mlb", D + "v.mls"}) {
        INFO(in);
        REQUIRE(sh("MESHLESS isosurface " + in + " --iso 60.5 -o " + D + "a.ply", d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + in + " --iso 150.5 -o " + D + "b.ply", d).code == 0);
        const auto r = sh("MESHLESS isosurface " + in + " --iso 150.5,60.5 -o " + D + "ba.ply --png " + D + "ba.png --stats", d);
        REQUIRE(r.code == 0);
        const std::string a = ply_body(d / "a.ply"), b = ply_body(d / "b.ply");
        REQUIRE(a.size() > 32 * 100);
        REQUIRE(b.size() > 32 * 100);
        CHECK(ply_body(d / "ba.ply") == b + a);  // in the order given
        const std::string h = ply_header(d / "ba.ply");
        CHECK_THAT(h, Catch::Contains("comment isovalues 150.5,60.5\n"));
        CHECK_THAT(h, !Catch::Contains("comment iso "));
        CHECK_THAT(h, Catch::Contains("element vertex " + std::to_string((a.size() + b.size()) / 32) + "\n"));
        CHECK(count_of(r.err, " iso 150.5: ") == 1);  // one --stats line per isovalue
        CHECK(count_of(r.err, " iso 60.5: ") == 1);
        // the picture colours each surface by its isovalue, as splat of the PLY draws it
        REQUIRE(sh("MESHLESS splat " + D + "ba.ply -o " + D + "ba_splat.png", d).code == 0);
        CHECK(slurp(d / "ba.png") == slurp(d / "ba_splat.png"));
        REQUIRE(sh("MESHLESS isosurface " + in + " --iso 60.5 --png " + D + "a.png", d).code == 0);
        CHECK(slurp(d / "ba.png") != slurp(d / "a.png"));
    }
    // a VTP holds the same points as the PLY
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 150.5,60.5 -o " + D + "ba.vtp", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 150.5,60.5 -o " + D + "ba2.ply", d).code == 0);
    const auto info = sh("MESHLESS info " + D + "ba.vtp", d);
    CHECK_THAT(info.out + info.err, Catch::Contains(std::to_string(ply_body(d / "ba2.ply").size() / 32)));
}

TEST_CASE("isosurface --iso lists: bad items, values outside the data, inputs that take one value", "[cli][isovalues]") {
    TempDir d("isovalues-bad");
    const std::string D = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "vol", AnalyticField::torus, 16, 200.0, 0.0);
    auto r = sh("MESHLESS isosurface " + vol + " --iso 60.5,,100 -o " + D + "x.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--iso: expected numbers separated by commas, got '60.5,,100'"));
    r = sh("MESHLESS isosurface " + vol + " --iso 60.5,nan -o " + D + "x.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--iso: expected a finite number, got 'nan'"));
    CHECK_FALSE(std::filesystem::exists(d / "x.ply"));
    // one value outside the data: its surface is empty, the run is not
    r = sh("MESHLESS isosurface " + vol + " --iso 60.5,999 -o " + D + "x.ply --fail-empty", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("isovalue 999 is outside the data range [13, 255]; its surface will be empty"));
    r = sh("MESHLESS isosurface " + vol + " --iso 998,999 -o " + D + "y.ply --fail-empty", d);
    CHECK(r.code == 4);
    CHECK(std::filesystem::exists(d / "y.ply"));
    // scattered points and mpirun take one isovalue a run
    std::string csv = "x,y,z,value\n";
    for (int k = 0; k < 5; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i)
                csv += std::to_string(i) + "," + std::to_string(j) + "," + std::to_string(k) + "," + std::to_string(i + j + k) + "\n";
    spit(d.path / "pts.csv", csv);
    r = sh("MESHLESS isosurface " + D + "pts.csv --iso 3.5,5.5 -o " + D + "p.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--iso: scattered points take one isovalue a run"));
    r = sh("OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 MESHLESS isosurface " + vol + " --iso 60.5,100.5 -o " + D + "m.ply", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("--iso: runs under mpirun take one isovalue a run"));
    CHECK_FALSE(std::filesystem::exists(d / "m.ply"));
}

TEST_CASE("mc --iso V1,V2: the single runs' meshes one after another, each welded on its own", "[cli][isovalues]") {
    TempDir d("isovalues-mc");
    const std::string D = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "vol", AnalyticField::torus, 24, 200.0, 0.0);
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "v.mlb --brick 8", d).code == 0);
    for (const std::string& in : {vol, D + "v.mlb"}) {
        INFO(in);
        REQUIRE(sh("MESHLESS mc " + in + " --iso 150.5 -o " + D + "a.ply", d).code == 0);
        REQUIRE(sh("MESHLESS mc " + in + " --iso 60.5 -o " + D + "b.ply", d).code == 0);
        const auto r = sh("MESHLESS mc " + in + " --iso 150.5,60.5 -o " + D + "ab.ply --stats --threads 2", d);
        REQUIRE(r.code == 0);
        CHECK(count_of(r.err, "mc: ") == 2);
        const Mesh a = read_ply_mesh(D + "a.ply"), b = read_ply_mesh(D + "b.ply"), ab = read_ply_mesh(D + "ab.ply");
        REQUIRE(a.triangle_count() > 100);
        REQUIRE(b.triangle_count() > 100);
        std::vector<float> xyz = a.xyz, normals = a.normals;
        xyz.insert(xyz.end(), b.xyz.begin(), b.xyz.end());
        normals.insert(normals.end(), b.normals.begin(), b.normals.end());
        std::vector<std::uint32_t> tri = a.tri;
        for (std::uint32_t t : b.tri) tri.push_back(t + static_cast<std::uint32_t>(a.vertex_count()));
        CHECK(ab.xyz == xyz);
        CHECK(ab.normals == normals);
        CHECK(ab.tri == tri);
    }
    auto r = sh("MESHLESS mc " + vol + " --iso 150.5,999 -o " + D + "c.ply", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("isovalue 999 is outside the data range"));
    CHECK_THAT(r.err, Catch::Contains("its surface will be empty"));
}

TEST_CASE("generate --iso V1,V2 | project | write: isosurface --iso V1,V2's bytes, one stream segment each", "[cli][isovalues]") {
    TempDir d("isovalues-pipe");
    const std::string D = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "vol", AnalyticField::torus, 24, 200.0, 0.0);
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "v.mlb --brick 8", d).code == 0);
    for (const std::string& in : {vol, D + "v.mlb"}) {
        INFO(in);
        REQUIRE(sh("MESHLESS isosurface " + in + " --iso 150.5,60.5 -o " + D + "i.ply --png " + D + "i.png --size 200x200", d).code == 0);
        const auto r = sh("MESHLESS generate " + in + " --iso 150.5,60.5 --stats | MESHLESS project --stats --threads 2 | MESHLESS write -o " +
                              D + "p.ply",
                          d);
        REQUIRE(r.code == 0);
        CHECK(count_of(r.err, "generate: ") == 2);
        CHECK(count_of(r.err, "project: ") == 2);
        CHECK(slurp(d / "p.ply") == slurp(d / "i.ply"));
        REQUIRE(sh("MESHLESS generate " + in + " --iso 150.5,60.5 --compress | MESHLESS project --compress | MESHLESS splat -o " + D +
                       "p.png --size 200x200",
                   d)
                    .code == 0);
        CHECK(slurp(d / "p.png") == slurp(d / "i.png"));
    }
    // one isovalue keeps the stream of one segment-free run
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 60.5 -o " + D + "one.samples", d).code == 0);
    CHECK_THAT(sh("MESHLESS info " + D + "one.samples", d).out, !Catch::Contains("segments"));
    // the stream lists its segments; what cannot take several isovalues says so
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 150.5,60.5 -o " + D + "s.samples", d).code == 0);
    auto r = sh("MESHLESS info " + D + "s.samples", d);
    CHECK_THAT(r.out, Catch::Contains("segments: 2 (records per isovalue: 150.5: "));
    CHECK_THAT(r.out, Catch::Contains("isovalues: 150.5,60.5"));
    r = sh("MESHLESS project " + D + "s.samples --iso 100 -o " + D + "x.points", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("s.samples holds the samples of 2 isovalues (150.5,60.5), each projected onto its own; drop --iso"));
    CHECK_FALSE(std::filesystem::exists(d / "x.points"));
    r = sh("MESHLESS splat " + D + "s.samples -o " + D + "x.png", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Catch::Contains("holds the samples of several isovalues (150.5,60.5); project them first"));
}

TEST_CASE("project refuses segments that do not match the isovalues listed, and segments in a one-isovalue stream", "[cli][isovalues]") {
    TempDir d("isovalues-segments-bad");
    const std::string D = d.path.string() + "/";
    const auto write = [&](const std::string& name, const char* list, const std::vector<double>& segment_isos) {
        std::FILE* f = std::fopen((d.path / name).c_str(), "wb");
        REQUIRE(f);
        StreamWriter w(f, name, RecordKind::sample, false);
        StreamMeta m;
        if (*list) m.set("isovalues", list);
        else m.set("iso", 1.0);
        w.write_meta(m);
        for (std::size_t k = 0; k < segment_isos.size(); ++k) {
            StreamMeta keys;
            keys.set("iso", segment_isos[k]);
            w.write_segment(k, keys);
        }
        w.finish();
        std::fclose(f);
    };
    write("ok.samples", "1,2", {1, 2});
    write("wrong.samples", "1,2", {1, 3});
    write("short.samples", "1,2", {1});
    write("one.samples", "", {1});
    CHECK(sh("MESHLESS project " + D + "ok.samples -o " + D + "ok.points", d).code == 0);
    auto r = sh("MESHLESS project " + D + "wrong.samples -o " + D + "w.points", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("wrong.samples: segment 1 does not begin isovalue 2 of the 2 its metadata lists (1,2)"));
    r = sh("MESHLESS project " + D + "short.samples -o " + D + "s.points", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("short.samples: holds 1 segments for the 2 isovalues its metadata lists"));
    r = sh("MESHLESS project " + D + "one.samples -o " + D + "o.points", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("one.samples: a segment frame in a stream of one isovalue"));
    for (const char* out : {"w.points", "s.points", "o.points"}) CHECK_FALSE(std::filesystem::exists(d / out));
}
