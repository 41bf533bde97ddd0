// Tests for formats/oriented_points_vtp.hpp (splat's .vtp input). Oracles: round trips through the
// project's VTP writer (formats/vtp_writer.hpp: every record bit for bit, compressed or not, and the
// comments as written, escapes and all); hand-written ascii files for the records dropped; one
// must-fail file per defect class, each refused with a message naming the file and the defect.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../test_paths.hpp"
#include "point_record_samples.hpp"
#include "formats/oriented_points_vtp.hpp"
#include "formats/vtp_writer.hpp"
#include "kernels/errors.hpp"

using namespace meshless;
namespace fs = std::filesystem;

namespace {

PointRecord record(std::uint64_t i) { return test::sample_point_record(i); }

void write(const fs::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary);
    out << bytes;
}

/// An ascii PolyData file of one piece: `point_data` inside <PointData>, `points` the coordinates.
std::string ascii_vtp(const std::string& point_data, const std::string& points, int n, const std::string& piece_extra = "") {
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n"
           "<Piece NumberOfPoints=\"" + std::to_string(n) + "\"" + piece_extra + ">\n<PointData>\n" + point_data +
           "</PointData>\n<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">" + points +
           "</DataArray>\n</Points>\n</Piece>\n</PolyData>\n</VTKFile>\n";
}

std::string array(const std::string& name, int comps, const std::string& values) {
    return "<DataArray type=\"Float32\" Name=\"" + name + "\" NumberOfComponents=\"" + std::to_string(comps) +
           "\" format=\"ascii\">" + values + "</DataArray>\n";
}

}  // namespace

TEST_CASE("oriented vtp: the writer's records and comments read back bit for bit", "[vtp][oriented-vtp]") {
    meshless::test::TempDir d("oriented-vtp");
    const std::vector<std::string> comments = {"source head.nhdr", "iso 1000.5", "has -- dashes, <tags> & a \xff byte-",
                                               "bounds_lo 0,0,0"};
    for (const bool zlib : {true, false}) {
        INFO("zlib " << zlib);
        VtpOptions o;
        o.compression = zlib ? VtpCompression::zlib : VtpCompression::none;
        o.block_size = 1000;
        const fs::path path = d / "p.vtp";
        std::vector<PointRecord> want;
        for (std::uint64_t i = 0; i < 5003; ++i) want.push_back(record(i));
        {
            VtpPointWriter w(path.string(), comments, o);
            w.append(want);
            w.commit();
        }
        const OrientedPointsVtp got = read_oriented_points_vtp(path.string());
        CHECK(got.dropped == 0);
        CHECK(got.comments == comments);
        REQUIRE(got.points.size() == want.size());
        CHECK(std::memcmp(got.points.data(), want.data(), want.size() * sizeof(PointRecord)) == 0);
    }
}

TEST_CASE("oriented vtp: non-finite or degenerate records are dropped and counted, normals made unit", "[vtp][oriented-vtp]") {
    meshless::test::TempDir d("oriented-vtp-drop");
    const fs::path p = d / "a.vtp";
    // six points: good, NaN position, zero normal, radius 0, infinite value, a normal of length 2
    write(p, ascii_vtp(array("Normals", 3, "0 0 1 0 0 1 0 0 0 0 0 1 0 0 1 0 2 0") + array("radius", 1, "1 1 1 0 1 1") +
                           array("value", 1, "5 5 5 5 inf 5"),
                       "0 0 0 nan 0 0 1 1 1 2 2 2 3 3 3 4 4 4", 6));
    const OrientedPointsVtp r = read_oriented_points_vtp(p.string());
    CHECK(r.dropped == 4);
    REQUIRE(r.points.size() == 2);
    CHECK(r.points[0].normal[2] == 1.0f);
    CHECK(r.points[1].pos[0] == 4.0f);
    CHECK(r.points[1].normal[1] == 1.0f);
    // the value: "value", else the Scalars array, else 0
    write(p, ascii_vtp(array("Normals", 3, "0 0 1") + array("radius", 1, "1") + array("t", 1, "7"), "0 0 0", 1));
    CHECK(read_oriented_points_vtp(p.string()).points.at(0).value == 0.0f);
    std::string s = ascii_vtp(array("Normals", 3, "0 0 1") + array("radius", 1, "1") + array("t", 1, "7"), "0 0 0", 1);
    s.replace(s.find("<PointData>"), 11, "<PointData Scalars=\"t\">");
    write(p, s);
    CHECK(read_oriented_points_vtp(p.string()).points.at(0).value == 7.0f);
}

TEST_CASE("oriented vtp: one refusal per defect class, naming the file", "[vtp][oriented-vtp]") {
    meshless::test::TempDir d("oriented-vtp-bad");
    const fs::path p = d / "bad.vtp";
    const std::string good_data = array("Normals", 3, "0 0 1 0 0 1") + array("radius", 1, "1 1") + array("value", 1, "1 2");
    struct Bad {
        const char* what;
        std::string bytes;
        const char* message;
    };
    std::string image = ascii_vtp(good_data, "0 0 0 1 1 1", 2);
    image.replace(image.find("type=\"PolyData\""), 15, "type=\"ImageData\"");
    std::string truncated = ascii_vtp(good_data, "0 0 0 1 1 1", 2);
    truncated.resize(truncated.size() / 2);
    const Bad cases[] = {
        {"another VTK type", image, "expected PolyData"},
        {"a mesh", ascii_vtp(good_data, "0 0 0 1 1 1", 2, " NumberOfPolys=\"1\""), "is a surface mesh"},
        {"no normals", ascii_vtp(array("radius", 1, "1 1") + array("value", 1, "1 2"), "0 0 0 1 1 1", 2),
         "need a 3-component Normals and a 'radius' point array"},
        {"no radius", ascii_vtp(array("Normals", 3, "0 0 1 0 0 1"), "0 0 0 1 1 1", 2), "the arrays here: Normals"},
        {"normals of 2 components", ascii_vtp(array("Normals", 2, "0 1 0 1") + array("radius", 1, "1 1"), "0 0 0 1 1 1", 2),
         "has 2 components, expected 3"},
        {"an array shorter than NumberOfPoints", ascii_vtp(good_data, "0 0 0 1 1 1", 3), "bad.vtp"},
        {"an implausible NumberOfPoints", ascii_vtp(good_data, "0 0 0 1 1 1", 0).replace(
                                              ascii_vtp(good_data, "0 0 0 1 1 1", 0).find("NumberOfPoints=\"0\""), 18,
                                              "NumberOfPoints=\"99999999999\""),
         "implausible point count"},
        {"a truncated file", truncated, "bad.vtp"},
        {"no piece", "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\"><PolyData></PolyData></VTKFile>\n",
         "no <Piece>"},
    };
    for (const Bad& b : cases) {
        INFO(b.what);
        write(p, b.bytes);
        try {
            (void)read_oriented_points_vtp(p.string());
            FAIL("accepted");
        } catch (const FormatError& e) {
            CHECK_THAT(e.what(), Catch::Contains(p.string()));
            CHECK_THAT(e.what(), Catch::Contains(b.message));
        }
    }
}
