// The streaming splat sink from the command line (dissertation section 3.6): `isosurface --png`,
// `splat FILE.ply`, `generate | project | splat` and a brick store under a small --memory give the
// same picture, for both kernels and any thread count; the camera frames the surface recorded in the
// stream/PLY (not the volume); a PNG that cannot be written leaves no PLY behind.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "cli/cli_harness.hpp"
#include "formats/ply_points.hpp"
#include "formats/point_stream.hpp"
#include "formats/png_writer.hpp"
#include "kernels/splat_rasterizer.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

/// A 70^3 uint8 volume holding a ball of radius 9 voxels centred at (15, 18, 50): its surface
/// occupies a small corner of the volume.
std::string corner_ball(const TempDir& d) {
    const int n = 70;
    std::string bytes(static_cast<std::size_t>(n) * n * n, '\0');
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double r = std::sqrt((i - 15.0) * (i - 15.0) + (j - 18.0) * (j - 18.0) + (k - 50.0) * (k - 50.0));
                bytes[static_cast<std::size_t>(i + n * (j + n * k))] = static_cast<char>(static_cast<unsigned char>(std::clamp(200.0 - 10.0 * r, 0.0, 255.0)));
            }
    const std::string path = (d / "ball_70x70x70_uint8.raw").string();
    spit(path, bytes);
    return path;
}

std::string comment(const std::string& ply, const std::string& key) {
    const auto at = ply.find("comment " + key + " ");
    if (at == std::string::npos) return "";
    const auto start = at + 9 + key.size();
    return ply.substr(start, ply.find('\n', start) - start);
}

}  // namespace

TEST_CASE("splat: every path to a picture gives the same bytes, both kernels, any thread count", "[cli][splat]") {
    TempDir d("splatcli");
    const std::string vol = corner_ball(d), D = d.path.string();
    REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "/b.mlb --brick 32", d).code == 0);
    for (const char* k : {"quad", "ewa"}) {
        INFO(k);
        const std::string opt = std::string(" --size 96x80 --kernel ") + k;
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "/a.ply --png " + D + "/a.png" + opt, d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 --threads 2 --png " + D + "/t.png" + opt, d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + D + "/b.mlb --memory 1M --iso 100.5 --threads 3 --png " + D + "/m.png" + opt, d).code == 0);
        REQUIRE(sh("MESHLESS splat " + D + "/a.ply --threads 2 -o " + D + "/s.png" + opt, d).code == 0);
        REQUIRE(sh("MESHLESS generate " + vol + " --iso 100.5 | MESHLESS project | MESHLESS splat -o " + D + "/p.png" + opt, d).code == 0);
        const std::string a = slurp(d / "a.png");
        const Image img = read_png(D + "/a.png");
        std::size_t lit = 0;
        for (std::size_t i = 0; i < img.rgb.size(); i += 3) lit += img.rgb[i] || img.rgb[i + 1] || img.rgb[i + 2];
        // framed on the ball's block: about 8% of the pixels (framed on the volume it would be under 2%)
        CHECK(lit > img.rgb.size() / 3 / 25);
        CHECK(a == slurp(d / "t.png"));
        CHECK(a == slurp(d / "m.png"));
        CHECK(a == slurp(d / "s.png"));
        CHECK(a == slurp(d / "p.png"));
    }
    // the PLY records the surface bounds (the active 32-cell blocks) and keeps the volume's
    const std::string ply = slurp(d / "a.ply");
    CHECK(comment(ply, "bounds_lo") == "0,0,32");
    CHECK(comment(ply, "bounds_hi") == "32,32,64");
    CHECK(comment(ply, "volume_bounds_hi") == "69,69,69");
}

TEST_CASE("isosurface -o --png: a PNG that cannot be written leaves no PLY, an empty surface is a background image",
          "[cli][splat]") {
    TempDir d("splatfail");
    const std::string vol = corner_ball(d), D = d.path.string();
    auto r = sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "/a.ply --png " + D + "/nodir/a.png", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("nodir"));
    CHECK_FALSE(fs::exists(d / "a.ply"));
    r = sh("MESHLESS isosurface " + vol + " --iso 250.5 --png " + D + "/e.png --size 32x24", d);
    CHECK(r.code == 0);
    const Image img = read_png(D + "/e.png");
    REQUIRE(img.width == 32);
    for (auto c : img.rgb) REQUIRE(c == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "/ok.ply", d).code == 0);
    r = sh("TMPDIR=" + D + "/nodir MESHLESS splat " + D + "/ok.ply --kernel ewa -o " + D + "/x.png", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains(D + "/nodir/meshless-splat-spool-"));
    CHECK_FALSE(fs::exists(d / "x.png"));
}

TEST_CASE("splat: a PLY or a point stream without recorded bounds frames the points (a point spool)", "[cli][splat]") {
    TempDir d("splatnob");
    const std::string vol = corner_ball(d), D = d.path.string();
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "/a.ply", d).code == 0);
    const PlyPoints a = read_ply_points(D + "/a.ply");
    REQUIRE(a.points.size() > 100);
    const auto b = point_bounds(a.points);
    char lo[128], hi[128];
    std::snprintf(lo, sizeof lo, "bounds_lo %.9g,%.9g,%.9g", b[0].x, b[0].y, b[0].z);
    std::snprintf(hi, sizeof hi, "bounds_hi %.9g,%.9g,%.9g", b[1].x, b[1].y, b[1].z);
    write_ply_points(D + "/none.ply", a.points, {});
    write_ply_points(D + "/with.ply", a.points, {lo, hi});
    {  // a point stream whose META records no bounds, in a few DATA frames
        std::FILE* f = std::fopen((D + "/none.mls").c_str(), "wb");
        REQUIRE(f);
        StreamWriter w(f, "none.mls", RecordKind::point);
        w.write_meta(StreamMeta{});
        const std::size_t half = a.points.size() / 2;
        w.write_data(0, a.points.data(), half);
        w.write_data(1, a.points.data() + half, a.points.size() - half);
        w.finish();
        std::fclose(f);
    }
    for (const char* k : {"quad", "ewa"}) {
        INFO(k);
        const std::string opt = std::string(" --size 64x48 --kernel ") + k;
        REQUIRE(sh("MESHLESS splat " + D + "/none.ply" + opt + " -o " + D + "/n.png", d).code == 0);
        REQUIRE(sh("MESHLESS splat " + D + "/with.ply" + opt + " -o " + D + "/w.png", d).code == 0);
        REQUIRE(sh("MESHLESS splat " + D + "/a.ply" + opt + " -o " + D + "/s.png", d).code == 0);
        REQUIRE(sh("MESHLESS splat " + opt + " --threads 2 -o " + D + "/m.png < " + D + "/none.mls", d).code == 0);
        CHECK(slurp(d / "n.png") == slurp(d / "w.png"));
        CHECK(slurp(d / "m.png") == slurp(d / "w.png"));
        CHECK(slurp(d / "n.png") != slurp(d / "s.png"));  // the surface-block frame is a different picture
    }
}

TEST_CASE("a point or sample stream with a NaN or infinite record is refused by write, splat and project", "[cli][splat][hostile]") {
    TempDir d("nonfinite");
    const std::string D = d.path.string();
    PointRecord p{{1, 2, 3}, {0, 0, 1}, 0.5f, 7};
    std::vector<PointRecord> pts(100, p);
    for (std::size_t i = 0; i < pts.size(); ++i) pts[i].pos[0] = static_cast<float>(i);
    pts[57].normal[1] = std::numeric_limits<float>::quiet_NaN();
    SampleRecord s{{1, 1, 1}, {1, 0, 0}, 5, 0.5f, {0.5f, 0.5f, 0.5f}, {1, 1, 1}, {}};
    std::vector<SampleRecord> samples(10, s);
    samples[3].value = std::numeric_limits<float>::infinity();
    const auto write = [&](const std::string& name, RecordKind kind, const void* records, std::size_t n) {
        std::FILE* f = std::fopen((D + "/" + name).c_str(), "wb");
        REQUIRE(f);
        StreamWriter w(f, name, kind);
        w.write_meta(StreamMeta{});
        w.write_data(0, records, n);
        w.finish();
        std::fclose(f);
    };
    write("p.bin", RecordKind::point, pts.data(), pts.size());
    write("s.bin", RecordKind::sample, samples.data(), samples.size());
    for (const std::string& cmd : {"write -o " + D + "/w.ply < " + D + "/p.bin", "splat -o " + D + "/w.png --size 32x32 < " + D + "/p.bin",
                                   "project --iso 5 < " + D + "/s.bin > " + D + "/proj.bin",
                                   "splat --iso 5 -o " + D + "/s.png --size 32x32 < " + D + "/s.bin"}) {
        INFO(cmd);
        const auto r = sh("MESHLESS " + cmd, d);
        CHECK(r.code == 2);
        CHECK_THAT(r.err, Catch::Contains("holds a NaN or infinite number") && Catch::Contains(cmd.find("p.bin") != std::string::npos ? "point record 57" : "sample record 3"));
    }
    CHECK_FALSE(fs::exists(d.path / "w.ply"));
    CHECK_FALSE(fs::exists(d.path / "w.png"));
    CHECK_FALSE(fs::exists(d.path / "s.png"));
}

TEST_CASE("splat: a CSV point set or a PLY on stdin is refused with what it is", "[cli][splat]") {
    TempDir d("splatother");
    const std::string vol = corner_ball(d), D = d.path.string();
    REQUIRE(sh("MESHLESS sample " + vol + " --count 100 -o " + D + "/a.csv", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "/a.ply", d).code == 0);
    const auto v = sh("MESHLESS splat " + D + "/a.csv -o " + D + "/v.png", d);
    CHECK(v.code == 2);
    CHECK_THAT(v.err, Catch::Contains("a.csv: splat draws oriented points (.ply, .vtp, meshless point streams), not csv files"));
    const auto p = sh("cat " + D + "/a.ply | MESHLESS splat - -o " + D + "/p.png", d);
    CHECK(p.code == 2);
    CHECK_THAT(p.err, Catch::Contains("it is a PLY file: give its path"));
    CHECK(!std::filesystem::exists(d / "v.png"));
    CHECK(!std::filesystem::exists(d / "p.png"));
}

TEST_CASE("isosurface --png: the same picture with the footprints in memory or on disk (--memory 4K: 512 bytes of them in memory)", "[cli][splat]") {
    TempDir d("splattier");
    const std::string vol = corner_ball(d), D = d.path.string();
    for (const char* t : {"1", "2"}) {
        INFO("threads " << t);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 --threads " + t + " --png " + D + "/m.png", d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 --threads " + t + " --memory 4K --png " + D + "/f.png", d).code == 0);
        CHECK(slurp(d / "m.png") == slurp(d / "f.png"));
    }
}

TEST_CASE("splat --turntable: frame i is the picture at azimuth + 360 i / N, from a PLY or a pipe", "[cli][splat]") {
    TempDir d("turntable");
    const std::string vol = corner_ball(d), D = d.path.string();
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "/a.ply", d).code == 0);
    for (const char* k : {"quad", "ewa"}) {
        INFO(k);
        const std::string opt = std::string(" --size 80x60 --elevation 20 --kernel ") + k;
        auto r = sh("MESHLESS splat " + D + "/a.ply --turntable 4 --azimuth 10 --threads 2 -o " + D + "/t.png" + opt, d);
        REQUIRE(r.code == 0);
        CHECK_THAT(r.err, Catch::Contains("turntable of 4 frames"));
        REQUIRE(sh("MESHLESS generate " + vol + " --iso 100.5 | MESHLESS project | MESHLESS splat --turntable 4 --azimuth 10 "
                   "--threads 1 -o " + D + "/p.png" + opt, d).code == 0);
        for (int i = 0; i < 4; ++i) {
            const std::string frame = "t_00" + std::to_string(i) + ".png";
            REQUIRE(sh("MESHLESS splat " + D + "/a.ply --azimuth " + std::to_string(10 + 90 * i) + " -o " + D + "/one.png" + opt,
                       d).code == 0);
            CHECK(slurp(d / frame) == slurp(d / "one.png"));
            CHECK(slurp(d / ("p_00" + std::to_string(i) + ".png")) == slurp(d / "one.png"));
            if (i > 0) CHECK(slurp(d / frame) != slurp(d / "t_000.png"));
        }
    }
}

TEST_CASE("splat --view and --up: named views are the azimuth/elevation they stand for, bad values refused", "[cli][splat]") {
    TempDir d("splatview");
    const std::string vol = corner_ball(d), D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "b.ply", d).code == 0);
    auto png = [&](const std::string& opt, const std::string& name) {
        REQUIRE(sh("MESHLESS splat " + D + "b.ply --size 96x64" + opt + " -o " + D + name, d).code == 0);
        return slurp(d / name);
    };
    CHECK(png(" --view +z", "vz.png") == png(" --azimuth 180 --elevation 0", "a180.png"));
    CHECK(png(" --view -z", "vmz.png") == png(" --azimuth 0 --elevation 0", "a0.png"));
    CHECK(png(" --view -z --up y", "vmzy.png") == slurp(d / "a0.png"));
    CHECK(png(" --up z", "upz.png") != png("", "default.png"));
    CHECK(png(" --up -y", "upmy.png") != slurp(d / "default.png"));
    CHECK(sh("MESHLESS splat " + D + "b.ply --up w -o " + D + "x.png", d).code == 1);
    CHECK(sh("MESHLESS splat " + D + "b.ply --view +q -o " + D + "x.png", d).code == 1);
    CHECK(sh("MESHLESS splat " + D + "b.ply --view iso --azimuth 10 -o " + D + "x.png", d).code == 1);
}
