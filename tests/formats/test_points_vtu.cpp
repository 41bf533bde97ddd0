// The nodes of VTK XML UnstructuredGrid files (.vtu) as point sets (formats/points_vtu.hpp):
// files written by VTK's own writer (tests/formats/make_vtu.py, python3-vtk9; skipped with a warning
// without it) in every data mode, compressor and header type, against the analytic oracle the
// script's formulas give and against the same points written as .vtp; the NaN node dropped and
// counted; and one hand-written must-fail file per defect class (truncated appended data, bad
// base64, a compressed block claiming more than it can hold, a zlib stream inflating past its
// claim, NumberOfPoints overflow and beyond the file, missing Points, the wrong VTK type).
#include <zlib.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "error_of.hpp"
#include "format_test_util.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::error_of;
using meshless::test::TempDir;

namespace {

bool have_vtk() { return std::system("/usr/bin/python3 -c 'import vtk' >/dev/null 2>&1") == 0; }

// Runs tests/formats/make_vtu.py into `dir` (nan_node >= 0: that node's x is NaN).
void make_vtu(const TempDir& dir, int n, int nan_node = -1) {
    const std::string cmd = (nan_node >= 0 ? "NAN_NODE=" + std::to_string(nan_node) + " " : std::string()) +
                            "/usr/bin/python3 '" MESHLESS_SOURCE_DIR "/tests/formats/make_vtu.py' '" + dir.path.string() +
                            "' " + std::to_string(n);
    REQUIRE(std::system(cmd.c_str()) == 0);
}

// The script's node i.
Vec3 node(int i) { return {(i * 37 % 101) / 10.0, (i * 53 % 97) / 10.0, (i * 11 % 89) / 10.0}; }

const char* kModes[] = {"ascii-none-32",      "binary-none-32",     "binary-none-64",     "binary-zlib-32",
                        "binary-zlib-64",     "appended-none-32",   "appended-none-64",   "appended-zlib-32",
                        "appended-zlib-64",   "appended64-none-32", "appended64-none-64", "appended64-zlib-32",
                        "appended64-zlib-64"};

std::string vtu(const std::string& file_attrs, const std::string& piece, const std::string& appended = "") {
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\"" + file_attrs +
           ">\n<UnstructuredGrid>\n" + piece + "</UnstructuredGrid>\n" +
           (appended.empty() ? "" : "<AppendedData encoding=\"raw\">\n_" + appended + "\n</AppendedData>\n") + "</VTKFile>\n";
}

std::string u32(std::uint32_t v) {
    std::string s(4, '\0');
    std::memcpy(s.data(), &v, 4);
    return s;
}

const std::string kCells =
    "<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\n"
    "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n"
    "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray>\n</Cells>\n";

}  // namespace

TEST_CASE("VTU written by VTK: every data mode, zlib, UInt32/UInt64 headers, the nodes and arrays exact", "[scatter][vtu]") {
    if (!have_vtk()) {
        WARN("python3-vtk9 not installed: the VTK-written .vtu files are not tested");
        return;
    }
    TempDir d("ps-vtu");
    const int n = 500;
    make_vtu(d, n);
    const PointSet vtp = read_point_set((d / "same.vtp").string());
    for (const char* mode : kModes) {
        const std::string path = (d / (std::string(mode) + ".vtu")).string();
        INFO(path);
        const PointSetInfo info = probe_point_set(path);
        CHECK(info.format == "vtu");
        const PointSet& ps = info.set;
        REQUIRE(ps.size() == static_cast<std::size_t>(n));  // every node, those no cell references included
        CHECK(ps.value_name == "f");                         // the active scalars
        for (int i = 0; i < n; ++i) {
            const Vec3 p = node(i);
            REQUIRE(ps.pos[i].x == p.x);
            REQUIRE(ps.pos[i].y == p.y);
            REQUIRE(ps.pos[i].z == p.z);
            REQUIRE(ps.value[i] == p.x * p.x + p.y - p.z);
        }
        REQUIRE(vtp.size() == ps.size());
        for (std::size_t i = 0; i < ps.size(); ++i)
            REQUIRE((ps.pos[i].x == vtp.pos[i].x && ps.pos[i].y == vtp.pos[i].y && ps.pos[i].z == vtp.pos[i].z));
        CHECK(ps.value == vtp.value);
        bool cells_note = false;
        for (const std::string& note : info.notes) cells_note |= note.find("124 cells: not used") != std::string::npos;
        CHECK(cells_note);
        PointSetOptions o;
        o.value_name = "g";
        const PointSet g = read_point_set(path, o);
        for (int i = 0; i < n; ++i) REQUIRE(g.value[i] == i);
        o.value_name = "vec";  // a vector array by name: its norm
        for (double v : read_point_set(path, o).value) REQUIRE(v == 5.0);
        o.value_name = "nope";
        CHECK_THAT(error_of([&] { read_point_set(path, o); }), Catch::Contains("arrays: g, vec, f"));
    }
}

TEST_CASE("VTU: a NaN node is dropped and counted, refused in strict mode", "[scatter][vtu]") {
    if (!have_vtk()) {
        WARN("python3-vtk9 not installed: the VTK-written .vtu files are not tested");
        return;
    }
    TempDir d("ps-vtu-nan");
    make_vtu(d, 40, 7);
    for (const char* mode : {"ascii-none-32", "appended-zlib-64"}) {
        const std::string path = (d / (std::string(mode) + ".vtu")).string();
        const PointSet ps = read_point_set(path);
        CHECK(ps.size() == 39);
        CHECK(ps.dropped_nonfinite == 1);
        CHECK(ps.pos[7].x == node(8).x);
        PointSetOptions o;
        o.strict = true;
        CHECK_THAT(error_of([&] { read_point_set(path, o); }), Catch::Contains("strict"));
    }
}

TEST_CASE("VTU must-fail: one file per defect class, one line naming the file", "[scatter][vtu]") {
    TempDir d("ps-vtu-bad");
    const std::string points4 = "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">"
                                "0 0 0 1 0 0 0 1 0 0 0 1</DataArray>\n</Points>\n";
    auto piece = [&](const std::string& np, const std::string& body) {
        return "<Piece NumberOfPoints=\"" + np + "\" NumberOfCells=\"1\">\n" + body + kCells + "</Piece>\n";
    };
    auto bad = [&](const std::string& name, const std::string& bytes, const std::string& expect) {
        const std::string path = (d / name).string();
        meshless::test::write_file(path, bytes);
        const std::string m = error_of([&] { read_point_set(path); });
        INFO(name << ": " << m);
        CHECK(m.rfind(path + ": ", 0) == 0);
        CHECK(m.find('\n') == std::string::npos);
        CHECK_THAT(m, Catch::Contains(expect));
    };
    // the good file first: the must-fail ones differ from it in one defect each
    meshless::test::write_file((d / "good.vtu").string(), vtu("", piece("4", points4)));
    CHECK(read_point_set((d / "good.vtu").string()).size() == 4);

    const std::string appended_points =
        "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\n</Points>\n";
    {  // the file ends 20 bytes into a 48-byte array
        const std::string whole = vtu("", piece("4", appended_points), u32(48) + std::string(20, '\1'));
        bad("truncated.vtu", whole.substr(0, whole.find('_', whole.find("<AppendedData")) + 1 + 4 + 20), "truncated DataArray");
    }
    bad("base64.vtu",
        vtu("", piece("4", "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"binary\">MAAAA@@@"
                           "</DataArray>\n</Points>\n")),
        "bad base64");
    {  // a block of 384000 bytes claimed by 1 compressed byte (the file is padded so the count is plausible)
        const std::string blocks = u32(1) + u32(384000) + u32(384000) + u32(1) + "x";
        bad("claim.vtu",
            vtu(" compressor=\"vtkZLibDataCompressor\"",
                piece("16000", "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\n"
                               "</Points>\n") + "<!--" + std::string(4000, ' ') + "-->\n",
                blocks),
            "more than its 1 compressed bytes can hold");
    }
    {  // a zlib stream that inflates to 100000 bytes where its header claims 48
        std::string plain(100000, '\0');
        uLongf n = compressBound(plain.size());
        std::string z(n, '\0');
        REQUIRE(compress2(reinterpret_cast<Bytef*>(z.data()), &n, reinterpret_cast<const Bytef*>(plain.data()), plain.size(), 9) == Z_OK);
        z.resize(n);
        const std::string blocks = u32(1) + u32(48) + u32(48) + u32(static_cast<std::uint32_t>(z.size())) + z;
        bad("bomb.vtu", vtu(" compressor=\"vtkZLibDataCompressor\"", piece("4", appended_points), blocks),
            "decompresses to more than 48 bytes");
    }
    bad("overflow.vtu", vtu("", piece("9223372036854775807", points4)), "NumberOfPoints of piece 0");
    bad("beyond.vtu", vtu("", piece("1000000", points4)), "implausible point count");
    bad("negative.vtu", vtu("", piece("-4", points4)), "NumberOfPoints");
    bad("nopoints.vtu", vtu("", piece("4", "")), "has no <Points>");
    bad("twocomp.vtu",
        vtu("", piece("4", "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"2\" format=\"ascii\">0 0 0 0 0 0 0 0"
                           "</DataArray>\n</Points>\n")),
        "2 components, expected 3");
    bad("short.vtu", vtu("", piece("5", points4)), "has 12 ascii values, expected 15");
    bad("nopiece.vtu", vtu("", ""), "no <Piece>");
    {
        std::string poly = vtu("", piece("4", points4));
        poly.replace(poly.find("UnstructuredGrid\""), 16, "PolyData");
        bad("wrong.vtu", poly, "expected UnstructuredGrid");
    }
}
