// The volume recipes of convert, verify, synth, hierarchy, lod, split and sample without a command
// line (stream/brick_conversion.hpp, stream/store_verification.hpp, stream/cluster_hierarchy.hpp,
// stream/volume_split.hpp, stream/volume_sampling.hpp).
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "kernels/analytic_volumes.hpp"
#include "ooc/brick_converter.hpp"
#include "stream/brick_conversion.hpp"
#include "stream/cluster_hierarchy.hpp"
#include "stream/store_verification.hpp"
#include "stream/volume_sampling.hpp"
#include "stream/volume_split.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;

namespace {
bool same_positions(const PointSet& a, const PointSet& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a.pos[i].x != b.pos[i].x || a.pos[i].y != b.pos[i].y || a.pos[i].z != b.pos[i].z) return false;
    return true;
}
}  // namespace

TEST_CASE("sample_volume draws the same points for a seed, inside the volume", "[stream][sample]") {
    const Volume v = make_analytic_volume(AnalyticField::gyroid, 12);
    const VolumeSample a = sample_volume(v, 1000, 7, "gyroid");
    const VolumeSample b = sample_volume(v, 1000, 7, "gyroid");
    REQUIRE(a.points.size() == 1000);
    CHECK(same_positions(a.points, b.points));
    CHECK(a.points.value == b.points.value);
    CHECK(a.redrawn == 0);
    REQUIRE(a.points.blocks.size() == 1);
    CHECK(a.points.blocks[0].count == 1000);
    CHECK_FALSE(same_positions(sample_volume(v, 1000, 8, "gyroid").points, a.points));
}

TEST_CASE("a converted brick store verifies, and a small budget and damage are told apart", "[stream][verify]") {
    TempDir dir("volume-recipes");
    const std::string out = (dir / "g.mlb").string();
    ConvertParams p;
    p.brick_edge = 8;
    auto src = make_volume_source(make_analytic_volume(AnalyticField::gyroid, 20), "gyroid");
    const ConvertStats st = convert_to_brick_store(*src, out, p);
    CHECK(brick_conversion_report("convert", *src, out, p, st).rfind("convert: 20x20x20 ", 0) == 0);
    REQUIRE(verified_store_kind(out) == StoreKind::brick);
    const StoreVerdict ok = verify_store(out, StoreKind::brick, std::uint64_t{256} << 20);
    CHECK(ok.status == 0);
    CHECK(ok.message == "ok: " + std::to_string(st.bricks) + " bricks");
    CHECK(verify_store(out, StoreKind::brick, 16).status == 1);
    {
        std::fstream f(out, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(200);  // eight bytes of a brick overwritten: the damage verify must find (status 2)
        const char damage[8] = {'\x58', '\x58', '\x58', '\x58', '\x58', '\x58', '\x58', '\x58'};
        f.write(damage, sizeof damage);
    }
    CHECK(verify_store(out, StoreKind::brick, std::uint64_t{256} << 20).status == 2);
}

TEST_CASE("a cluster hierarchy of a point set and its levels of detail", "[stream][hierarchy]") {
    PointSet ps;
    ps.value_name = "f";
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j)
            for (int k = 0; k < 4; ++k) {
                ps.pos.push_back(Vec3{double(i), double(j), double(k)});
                ps.value.push_back(double(i * i) + j);
            }
    CbtParams p;
    p.max_splits = 30;
    const ClusterTree t = build_cluster_hierarchy(ps, p, 1, "grid");
    CHECK(t.value_name == "f");
    CHECK(t.stats.splits == 30);
    CHECK(cluster_hierarchy_notes(t, p).empty());
    CHECK(cluster_hierarchy_report(t, p, 1, 0, 0).rfind("hierarchy: 400 samples, 30 splits", 0) == 0);
    PointSetOptions o;
    o.lod_level = 2;
    const ClusterTreeLodRequest r = cluster_tree_lod_request(t, o);
    const LodExtraction e = extract_lod(t, r);
    CHECK(e.points.size() >= 2);
    CHECK(e.points.size() <= 4);
    CHECK(lod_report(t, r, "t.mlh", e).rfind("lod: level 2 of t.mlh: ", 0) == 0);
    p.max_splits = 0;
    const ClusterTree one = build_cluster_hierarchy(ps, p, 1, "grid");
    REQUIRE(cluster_hierarchy_notes(one, p).size() == 1);
    CHECK(cluster_hierarchy_notes(one, p)[0].rfind("note: --max-splits 0", 0) == 0);
}

TEST_CASE("write_volume_split writes the pieces and reports them", "[stream][split]") {
    TempDir dir("volume-split");
    const Volume v = make_analytic_volume(AnalyticField::gyroid, 16);
    VolumeSplitOptions o;
    o.split.blocks = 3;
    const std::string out = (dir / "g.vtm").string();
    std::FILE* report = std::tmpfile();
    REQUIRE(report);
    write_volume_split(v, o, out, report);
    std::rewind(report);
    std::string text;
    for (int c; (c = std::fgetc(report)) != EOF;) text += static_cast<char>(c);
    std::fclose(report);
    CHECK(std::filesystem::exists(out));
    CHECK(text.find("wrote " + out + " and 3 pieces") != std::string::npos);
}
