// PLY point sets: round trips (streamed and whole), the count patched into a fixed-width header,
// foreign encodings (ASCII, big endian), and must-fail inputs (garbage, truncation, bad header).
#include <catch2/catch.hpp>

#include <cstring>
#include <fstream>
#include <sstream>

#include "formats/ply_points.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;

namespace {

std::vector<PointRecord> pts(int n) {
    std::vector<PointRecord> v(n);
    for (int i = 0; i < n; ++i) {
        const float f[8] = {float(i), float(2 * i), float(-i), 0, 0, 1, 0.5f, float(i) / 7};
        std::memcpy(&v[i], f, sizeof f);
    }
    return v;
}

std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void spit(const std::filesystem::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

}  // namespace

TEST_CASE("PLY points round trip, streamed and whole, byte-identical", "[ply-points]") {
    TempDir d("plyp");
    const auto v = pts(1234);
    {
        PlyPointWriter w((d / "a.ply").string(), {"iso 3.5", "source x.raw"});
        w.append(std::span(v).subspan(0, 1000));
        w.append(std::span(v).subspan(1000));
        w.commit();
    }
    write_ply_points((d / "b.ply").string(), v, {"iso 3.5", "source x.raw"});
    CHECK(slurp(d / "a.ply") == slurp(d / "b.ply"));
    const PlyPoints back = read_ply_points((d / "a.ply").string());
    REQUIRE(back.points.size() == v.size());
    CHECK(std::memcmp(back.points.data(), v.data(), v.size() * sizeof(PointRecord)) == 0);
    CHECK(back.comments.at(0) == "iso 3.5");
    for (const auto& e : std::filesystem::directory_iterator(d.path)) CHECK(e.path().string().find(".tmp-") == std::string::npos);
}

TEST_CASE("PLY points: an unfinished writer leaves nothing behind", "[ply-points]") {
    TempDir d("plyq");
    {
        PlyPointWriter w((d / "a.ply").string(), {});
        w.append(pts(10));
    }
    CHECK(std::filesystem::is_empty(d.path));
    CHECK_THROWS_AS(PlyPointWriter((d / "no/dir/a.ply").string(), {}), IoError);
}

TEST_CASE("PLY points: ASCII and big-endian files with other property sets", "[ply-points]") {
    TempDir d("plyr");
    spit(d / "a.ply", "ply\nformat ascii 1.0\ncomment hi\nelement vertex 2\nproperty double x\nproperty double y\n"
                      "property double z\nproperty uchar red\nend_header\n1 2 3 255\n4 5 6 0\n");
    const auto a = read_ply_points((d / "a.ply").string());
    REQUIRE(a.points.size() == 2);
    CHECK(a.points[1].pos[2] == 6.0f);
    CHECK(a.points[1].radius == 0.0f);
    std::string be = "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                     "property float value\nend_header\n";
    for (float f : {1.5f, -2.0f, 3.25f, 9.0f}) {
        unsigned char b[4];
        std::memcpy(b, &f, 4);
        be += std::string{char(b[3]), char(b[2]), char(b[1]), char(b[0])};
    }
    spit(d / "b.ply", be);
    const auto b = read_ply_points((d / "b.ply").string());
    REQUIRE(b.points.size() == 1);
    CHECK(b.points[0].pos[1] == -2.0f);
    CHECK(b.points[0].value == 9.0f);
}

TEST_CASE("PLY points: garbage, truncation, bad headers are refused", "[ply-points]") {
    TempDir d("plys");
    write_ply_points((d / "good.ply").string(), pts(20), {});
    const std::string good = slurp(d / "good.ply");
    spit(d / "x.ply", "hello");
    CHECK_THROWS_WITH(read_ply_points((d / "x.ply").string()), Catch::Contains("not a PLY file"));
    for (std::size_t cut : {good.size() - 1, good.size() - 32, good.find("end_header") + 3, std::size_t(10)}) {
        spit(d / "t.ply", good.substr(0, cut));
        CHECK_THROWS_AS(read_ply_points((d / "t.ply").string()), FormatError);
    }
    spit(d / "trail.ply", good + "xx");
    CHECK_THROWS_WITH(read_ply_points((d / "trail.ply").string()), Catch::Contains("trailing bytes"));
    std::string v2 = good;
    v2.replace(v2.find("1.0"), 3, "2.0");
    spit(d / "v2.ply", v2);
    CHECK_THROWS_WITH(read_ply_points((d / "v2.ply").string()), Catch::Contains("unsupported PLY version"));
    std::string noxyz = good;
    noxyz.replace(noxyz.find("property float x\n"), 17, "property float q\n");
    spit(d / "noxyz.ply", noxyz);
    CHECK_THROWS_WITH(read_ply_points((d / "noxyz.ply").string()), Catch::Contains("no x y z"));
    CHECK_THROWS_AS(read_ply_points((d / "missing.ply").string()), IoError);
}

TEST_CASE("PLY points with a block property: written streamed and whole, read back with their ids", "[ply-points]") {
    TempDir d("plyb");
    const auto v = pts(300);
    std::vector<std::uint32_t> blk(v.size());
    for (std::size_t i = 0; i < blk.size(); ++i) blk[i] = static_cast<std::uint32_t>(i % 3 == 0 ? 4000000000u : i % 5);
    {
        PlyPointWriter w((d / "a.ply").string(), {"blocks 5"}, /*with_blocks=*/true);
        w.append(std::span(v).subspan(0, 100), std::span(blk).subspan(0, 100));
        w.append(std::span(v).subspan(100), std::span(blk).subspan(100));
        CHECK_THROWS_AS(w.append(std::span(v).subspan(0, 2)), std::invalid_argument);  // ids missing
        w.commit();
    }
    write_ply_points((d / "b.ply").string(), v, {"blocks 5"}, std::span<const std::uint32_t>(blk));
    CHECK(slurp(d / "a.ply") == slurp(d / "b.ply"));
    CHECK(slurp(d / "a.ply").find("property float value\nproperty uint block\nend_header") != std::string::npos);
    const PlyPoints back = read_ply_points((d / "a.ply").string());
    REQUIRE(back.points.size() == v.size());
    CHECK(std::memcmp(back.points.data(), v.data(), v.size() * sizeof(PointRecord)) == 0);
    CHECK(back.block == blk);
    // an empty multiblock output still declares the property
    write_ply_points((d / "e.ply").string(), {}, {}, std::span<const std::uint32_t>());
    CHECK(slurp(d / "e.ply").find("property uint block") != std::string::npos);
    PlyPointReader er((d / "e.ply").string());
    CHECK(er.has_blocks());
    // files without the property read no ids
    write_ply_points((d / "c.ply").string(), v, {});
    CHECK(read_ply_points((d / "c.ply").string()).block.empty());
    CHECK_THROWS_AS(PlyPointWriter((d / "x.ply").string(), {}).append(v, blk), std::invalid_argument);
}

TEST_CASE("PLY points: ASCII block ids are read, non-integer or float block properties refused", "[ply-points]") {
    TempDir d("plyc");
    spit(d / "a.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                      "property int block\nend_header\n1 2 3 5\n4 5 6 0\n");
    const auto a = read_ply_points((d / "a.ply").string());
    CHECK(a.block == std::vector<std::uint32_t>{5, 0});
    spit(d / "n.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                      "property int block\nend_header\n1 2 3 -1\n");
    CHECK_THROWS_WITH(read_ply_points((d / "n.ply").string()), Catch::Contains("vertex 0: block -1"));
    spit(d / "f.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                      "property float block\nend_header\n1 2 3 1.5\n");
    CHECK_THROWS_WITH(read_ply_points((d / "f.ply").string()), Catch::Contains("'block' must be an integer type"));
}
