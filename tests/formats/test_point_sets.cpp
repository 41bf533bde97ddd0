// Scattered and multiblock point-set readers and writers: generated files in every layout with
// analytic oracles (values are functions of the positions), bad inputs, and the real data of
// shared/data/SOURCES.md sections 2 and 3.
#include <catch2/catch.hpp>

#include "error_of.hpp"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "format_test_util.hpp"
#include "formats/base64.hpp"
#include "formats/plot3d.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/point_set_writer.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;

namespace {

double fval(double x, double y, double z) { return 2.0 * x - 0.5 * y + 3.0 * z + 1.0; }

std::string P(const TempDir& d, const std::string& n) { return (d / n).string(); }

void spit(const std::string& p, const std::string& s) { meshless::test::write_file(p, s); }
void spit_bytes(const std::string& p, const std::vector<std::byte>& b) { meshless::test::write_file(p, "", b); }

std::vector<std::byte> read_all(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::vector<char> c((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::byte> b(c.size());
    std::memcpy(b.data(), c.data(), c.size());
    return b;
}

template <class T>
void put(std::vector<std::byte>& out, T v, bool big) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big) std::reverse(b, b + sizeof(T));
    for (unsigned char c : b) out.push_back(static_cast<std::byte>(c));
}

/// Synthetic scattered set: positions deterministic, value = fval.
PointSet make_set(std::size_t n, double offset = 0, std::array<double, 3> scale = {1, 1, 1}) {
    PointSet ps;
    for (std::size_t i = 0; i < n; ++i) {
        const double u = std::fmod(i * 0.6180339887, 1.0), v = std::fmod(i * 0.7548776662, 1.0), w = std::fmod(i * 0.5698402910, 1.0);
        const Vec3 p{offset + u * scale[0], offset + v * scale[1], offset + w * scale[2]};
        ps.pos.push_back(p);
        ps.value.push_back(fval(p.x, p.y, p.z));
    }
    ps.value_name = "value";
    ps.blocks = {PointSetBlock{"points", {static_cast<std::int64_t>(n), 1, 1}, 0, n}};
    return ps;
}

void require_same(const PointSet& a, const PointSet& b, double tol = 0) {
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        REQUIRE(std::fabs(a.pos[i].x - b.pos[i].x) <= tol);
        REQUIRE(std::fabs(a.pos[i].y - b.pos[i].y) <= tol);
        REQUIRE(std::fabs(a.pos[i].z - b.pos[i].z) <= tol * 10);
        REQUIRE(std::fabs(a.value[i] - b.value[i]) <= tol * 10 + 0);
    }
}


/// The reader's message: a FormatError or an IoError (tests/error_of.hpp).
template <class F>
std::string error_of(F&& f) {
    return test::error_of<FormatError, IoError>(f);
}

}  // namespace

// ---------------------------------------------------------------- text

TEST_CASE("text: CSV and PLY written by the writers read back exactly, 1e6 offsets and anisotropic scales", "[scatter]") {
    TempDir d("ps-text");
    for (double offset : {0.0, 1e6}) {
        const PointSet ps = make_set(200, offset, {1e-3, 1.0, 1e4});
        write_point_set(P(d, "a.csv"), ps);
        write_point_set(P(d, "a.ply"), ps);
        const PointSet c = read_point_set(P(d, "a.csv"));
        const PointSet p = read_point_set(P(d, "a.ply"));
        require_same(ps, c);  // 17 significant digits: exact
        require_same(ps, p);  // doubles: exact
        CHECK(c.value_name == "value");
        CHECK(p.value_name == "value");
        CHECK(c.has_values);
        // sub-micrometre differences survive the 1e6 offset
        CHECK(c.pos[1].x - c.pos[0].x == Approx(ps.pos[1].x - ps.pos[0].x).margin(1e-12));
    }
}

TEST_CASE("text: header, delimiters, CRLF, comments, column choice", "[scatter]") {
    TempDir d("ps-text2");
    std::string tsv = "# comment\r\nx\ty\tz\tval\r\n", ws = "", semi = "px;py;pz;t;s\n";
    for (int i = 0; i < 10; ++i) {
        const double x = i * 0.5, y = i * 0.25 - 1, z = 3 - i * 0.125;
        char b[256];
        std::snprintf(b, sizeof b, "%.17g\t%.17g\t%.17g\t%.17g\r\n", x, y, z, fval(x, y, z));
        tsv += b;
        std::snprintf(b, sizeof b, "  %.17g   %.17g %.17g %.17g 99\n", x, y, z, fval(x, y, z));
        ws += b;
        std::snprintf(b, sizeof b, "%.17g;%.17g;%.17g;7;%.17g\n", x, y, z, fval(x, y, z));
        semi += b;
    }
    spit(P(d, "a.tsv"), tsv);
    spit(P(d, "b.txt"), ws);
    spit(P(d, "c.csv"), semi);
    for (const char* f : {"a.tsv", "b.txt"}) {
        const PointSet ps = read_point_set(P(d, f));
        REQUIRE(ps.size() == 10);
        for (std::size_t i = 0; i < ps.size(); ++i) CHECK(ps.value[i] == fval(ps.pos[i].x, ps.pos[i].y, ps.pos[i].z));
    }
    CHECK(read_point_set(P(d, "a.tsv")).value_name == "val");
    PointSetOptions o;
    o.columns = "px,py,pz,s";
    PointSet c = read_point_set(P(d, "c.csv"), o);
    for (std::size_t i = 0; i < c.size(); ++i) CHECK(c.value[i] == fval(c.pos[i].x, c.pos[i].y, c.pos[i].z));
    o.columns = "0,1,2,4";
    c = read_point_set(P(d, "c.csv"), o);
    for (std::size_t i = 0; i < c.size(); ++i) CHECK(c.value[i] == fval(c.pos[i].x, c.pos[i].y, c.pos[i].z));
    o = {};
    o.value_name = "t";
    c = read_point_set(P(d, "c.csv"), o);
    for (double v : c.value) CHECK(v == 7);
    o = {};
    o.columns = "x,y,z";
    const PointSet pos_only = read_point_set(P(d, "a.tsv"), o);
    CHECK_FALSE(pos_only.has_values);
    o = {};
    o.value_index = 4;
    c = read_point_set(P(d, "b.txt"), o);
    for (double v : c.value) CHECK(v == 99);
}

TEST_CASE("text: count line, tagged .pts lines, positions only", "[scatter]") {
    TempDir d("ps-text3");
    std::string cnt = "5\n", pts = "# x\nd 1 1 1\ns 1 1 1\n";
    for (int i = 0; i < 5; ++i) {
        cnt += std::to_string(i) + " " + std::to_string(2 * i) + " 1 " + std::to_string(fval(i, 2 * i, 1)) + " 0.05\n";
        pts += "p " + std::to_string(i) + " 0.5 " + std::to_string(-i) + "\n";
    }
    spit(P(d, "g.txt"), cnt);
    spit(P(d, "c.pts"), pts);
    const PointSet g = read_point_set(P(d, "g.txt"));
    REQUIRE(g.size() == 5);
    for (std::size_t i = 0; i < 5; ++i) CHECK(g.value[i] == Approx(fval(g.pos[i].x, g.pos[i].y, g.pos[i].z)));
    const PointSet c = read_point_set(P(d, "c.pts"));
    REQUIRE(c.size() == 5);
    CHECK_FALSE(c.has_values);
    CHECK(c.pos[4].z == -4);
    spit(P(d, "bad.txt"), "6\n" + cnt.substr(2));
    CHECK_THAT(error_of([&] { read_point_set(P(d, "bad.txt")); }), Catch::Contains("says 6 points, the file has 5"));
    // counts no file can hold or that are not whole (fuzz_csv: 1.1e53 overflowed the conversion to an integer)
    for (const char* count : {"1.11111e53", "1e300", "2.5", "-1"}) {
        spit(P(d, "huge.txt"), std::string(count) + "\n" + cnt.substr(2));
        CHECK_THAT(error_of([&] { read_point_set(P(d, "huge.txt")); }), Catch::Contains("huge.txt: line 1: bad point count"));
    }
}

TEST_CASE("text: bad input gives one-line errors naming the file", "[scatter]") {
    TempDir d("ps-text-bad");
    auto err = [&](const std::string& name, const std::string& text, const PointSetOptions& o = {}) {
        spit(P(d, name), text);
        const std::string e = error_of([&] { read_point_set(P(d, name), o); });
        CHECK(e.rfind(P(d, name) + ": ", 0) == 0);
        CHECK(e.find('\n') == std::string::npos);
        return e;
    };
    CHECK_THAT(err("empty.csv", ""), Catch::Contains("empty"));
    CHECK_THAT(err("comments.csv", "# nothing\n\n# here\n"), Catch::Contains("empty"));
    CHECK_THAT(err("three.csv", "x,y,z,v\n0,0,0,1\n1,0,0,1\n0,1,0,1\n"), Catch::Contains("at least 4"));
    CHECK_THAT(err("dup.csv", "x,y,x,v\n0,0,0,1\n"), Catch::Contains("malformed header"));
    CHECK_THAT(err("mixed.csv", "x,y,3,v\n0,0,0,1\n"), Catch::Contains("malformed header"));
    CHECK_THAT(err("emptyname.csv", "x,,z,v\n0,0,0,1\n"), Catch::Contains("malformed header"));
    CHECK_THAT(err("fields.csv", "x,y,z,v\n0,0,0,1\n0,0,1\n"), Catch::Contains("line 3"));
    CHECK_THAT(err("number.csv", "x,y,z,v\n0,0,0,1\n0,abc,0,1\n"), Catch::Contains("bad number 'abc'"));
    PointSetOptions o;
    o.columns = "x,y,z,rho";
    CHECK_THAT(err("missing.csv", "x,y,z,v\n0,0,0,1\n", o), Catch::Contains("missing column 'rho'"));
    o.columns = "0,1,7,3";
    CHECK_THAT(err("missing2.csv", "x,y,z,v\n0,0,0,1\n", o), Catch::Contains("missing column 7"));
    CHECK_THAT(err("two.txt", "1 2\n3 4\n"), Catch::Contains("need at least 3"));
    // binary content no reader claims: named for what it is (was "not a text file (NUL bytes)")
    CHECK_THAT(err("picture.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16)),
               Catch::Contains("a PNG image, not a volume or point set"));
    CHECK_THAT(err("blob.dat2", std::string("\x01\x02\0\0\x7f", 5)), Catch::Contains("binary data of no known format"));
    // an outlier beyond 1e150 units: squared distances would overflow (fields merged every point into one)
    CHECK_THAT(err("outlier.csv", "x,y,z,v\n0,0,0,1\n1,0,0,1\n0,1,0,1\n0,0,1,1\n0,0,1e300,2\n"),
               Catch::Contains("z coordinates span 0 .. 1e+300, more than 1e+150 units"));
    spit(P(d, "far.csv"), "x,y,z,v\n0,0,0,1\n1e149,0,0,1\n0,1,0,1\n0,0,1,1\n");  // the bound itself is not refused
    CHECK(read_point_set(P(d, "far.csv")).size() == 4);
}

TEST_CASE("text: NaN/Inf samples are dropped and counted, or refused with the line in strict mode", "[scatter]") {
    TempDir d("ps-nan");
    std::string t = "x,y,z,v\n";
    for (int i = 0; i < 8; ++i) t += std::to_string(i) + ",0,0," + std::to_string(i) + "\n";
    t += "nan,0,0,1\n1,2,3,inf\n";
    spit(P(d, "n.csv"), t);
    const PointSet ps = read_point_set(P(d, "n.csv"));
    CHECK(ps.size() == 8);
    CHECK(ps.dropped_nonfinite == 2);
    for (double v : ps.value) CHECK(std::isfinite(v));
    PointSetOptions o;
    o.strict = true;
    CHECK_THAT(error_of([&] { read_point_set(P(d, "n.csv"), o); }), Catch::Contains("line 10: non-finite coordinate"));
    // all but three dropped -> too few
    spit(P(d, "few.csv"), "x,y,z,v\n0,0,0,1\n1,0,0,nan\n2,0,0,nan\n0,1,0,2\n0,0,1,3\n");
    CHECK_THAT(error_of([&] { read_point_set(P(d, "few.csv")); }), Catch::Contains("2 NaN/Inf"));
}

// ---------------------------------------------------------------- PLY

TEST_CASE("PLY: ASCII and big-endian binary, scalar by name and by default, elements around the vertices", "[scatter]") {
    TempDir d("ps-ply");
    const PointSet ref = make_set(20, 5.0);
    std::string a = "ply\nformat ascii 1.0\ncomment hi\nelement vertex 20\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float nx\nproperty uchar flag\nproperty double intensity\nproperty float other\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n";
    std::vector<std::byte> bin;
    std::string bh = "ply\nformat binary_big_endian 1.0\nelement face 2\nproperty list uchar int vertex_indices\n"
                     "element vertex 20\nproperty double x\nproperty double y\nproperty double z\nproperty float nx\n"
                     "property uchar flag\nproperty double intensity\nproperty float other\nend_header\n";
    for (char c : bh) bin.push_back(static_cast<std::byte>(c));
    for (int f = 0; f < 2; ++f) {
        put<std::uint8_t>(bin, 3, true);
        for (int k = 0; k < 3; ++k) put<std::int32_t>(bin, k, true);
    }
    for (std::size_t i = 0; i < ref.size(); ++i) {
        const auto& p = ref.pos[i];
        char b[256];
        std::snprintf(b, sizeof b, "%.9g %.9g %.9g 0 1 %.17g -1\n", static_cast<float>(p.x), static_cast<float>(p.y),
                      static_cast<float>(p.z), ref.value[i]);
        a += b;
        put<double>(bin, p.x, true);
        put<double>(bin, p.y, true);
        put<double>(bin, p.z, true);
        put<float>(bin, 0.f, true);
        put<std::uint8_t>(bin, 1, true);
        put<double>(bin, ref.value[i], true);
        put<float>(bin, -1.f, true);
    }
    a += "3 0 1 2\n";
    spit(P(d, "a.ply"), a);
    spit_bytes(P(d, "b.ply"), bin);
    for (const char* f : {"a.ply", "b.ply"}) {
        const PointSet ps = read_point_set(P(d, f));
        REQUIRE(ps.size() == 20);
        CHECK(ps.value_name == "intensity");  // first float property that is not x y z or a normal
        for (std::size_t i = 0; i < ps.size(); ++i) CHECK(ps.value[i] == ref.value[i]);
        PointSetOptions o;
        o.value_name = "other";
        for (double v : read_point_set(P(d, f), o).value) CHECK(v == -1);
        o.value_name = "nope";
        CHECK_THAT(error_of([&] { read_point_set(P(d, f), o); }), Catch::Contains("no vertex property 'nope'"));
    }
    require_same(read_point_set(P(d, "b.ply")), ref);  // doubles exact
    bin.resize(bin.size() - 7);
    spit_bytes(P(d, "t.ply"), bin);
    CHECK_THAT(error_of([&] { read_point_set(P(d, "t.ply")); }), Catch::Contains("truncated"));
    spit(P(d, "h.ply"), "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nbogus line\nend_header\n");
    CHECK_THAT(error_of([&] { read_point_set(P(d, "h.ply")); }), Catch::Contains("malformed PLY header"));
}

// ---------------------------------------------------------------- VTK XML

namespace {

// A DataArray payload in one of the VTK encodings.
struct VtkEnc {
    std::string format;  // ascii | binary | appended-raw | appended-base64
    bool zlib = false, header64 = false, big = false;
};

std::vector<std::byte> vtk_block(const std::vector<std::byte>& data, const VtkEnc& e) {
    std::vector<std::byte> out;
    auto hdr = [&](std::uint64_t v) {
        if (e.header64) put<std::uint64_t>(out, v, e.big);
        else put<std::uint32_t>(out, static_cast<std::uint32_t>(v), e.big);
    };
    if (!e.zlib) {
        hdr(data.size());
        out.insert(out.end(), data.begin(), data.end());
        return out;
    }
    // two blocks to exercise the block table
    const std::size_t bs = (data.size() + 1) / 2 + 3;
    std::vector<std::vector<std::byte>> blocks;
    for (std::size_t o = 0; o < data.size(); o += bs)
        blocks.push_back(meshless::test::deflate_bytes(data.data() + o, std::min(bs, data.size() - o), false));
    hdr(blocks.size());
    hdr(bs);
    hdr(data.size() - (blocks.size() - 1) * bs);
    for (auto& b : blocks) hdr(b.size());
    for (auto& b : blocks) out.insert(out.end(), b.begin(), b.end());
    return out;
}

std::string vtk_file(const std::string& type, const std::vector<std::pair<std::string, std::string>>& pieces_xml,
                     const std::vector<std::byte>& appended, const VtkEnc& e, bool appended_b64) {
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + type + "\" version=\"1.0\" byte_order=\"" +
                    (e.big ? "BigEndian" : "LittleEndian") + "\" header_type=\"" + (e.header64 ? "UInt64" : "UInt32") + "\"" +
                    (e.zlib ? " compressor=\"vtkZLibDataCompressor\"" : "") + ">\n";
    s += "<" + type + (type == "StructuredGrid" ? " WholeExtent=\"" + pieces_xml.front().first + "\"" : std::string()) + ">\n";
    for (const auto& [ext, body] : pieces_xml) s += body;
    s += "</" + type + ">\n";
    if (!appended.empty()) {
        s += std::string("<AppendedData encoding=\"") + (appended_b64 ? "base64" : "raw") + "\">\n_";
        s.append(reinterpret_cast<const char*>(appended.data()), appended.size());
        s += "\n</AppendedData>\n";
    }
    return s + "</VTKFile>\n";
}

// One DataArray element; appended payloads go to `app`.
std::string vtk_array(const std::string& attrs, const std::vector<double>& v, bool f64, const VtkEnc& e,
                      std::vector<std::byte>& app) {
    const std::string type = f64 ? "Float64" : "Float32";
    if (e.format == "ascii") {
        std::string s = "<DataArray type=\"" + type + "\" " + attrs + " format=\"ascii\">\n";
        char b[64];
        for (double x : v) {
            std::snprintf(b, sizeof b, "%.17g ", f64 ? x : static_cast<double>(static_cast<float>(x)));
            s += b;
        }
        return s + "\n</DataArray>\n";
    }
    std::vector<std::byte> raw;
    for (double x : v) {
        if (f64) put<double>(raw, x, e.big);
        else put<float>(raw, static_cast<float>(x), e.big);
    }
    const auto blk = vtk_block(raw, e);
    if (e.format == "binary")
        return "<DataArray type=\"" + type + "\" " + attrs + " format=\"binary\">\n" + base64_encode(blk.data(), blk.size()) +
               "\n</DataArray>\n";
    const std::size_t off = app.size();
    if (e.format == "appended-base64") {  // each array is its own base64 run
        const std::string t = base64_encode(blk.data(), blk.size());
        for (char c : t) app.push_back(static_cast<std::byte>(c));
    } else {
        app.insert(app.end(), blk.begin(), blk.end());
    }
    return "<DataArray type=\"" + type + "\" " + attrs + " format=\"appended\" offset=\"" + std::to_string(off) + "\"/>\n";
}

}  // namespace

TEST_CASE("VTP: ascii, base64, appended raw/base64, zlib, UInt64 headers, big endian, array choice", "[scatter]") {
    TempDir d("ps-vtp");
    const PointSet ref = make_set(37, 2.0);
    std::vector<double> xyz, val, other, vec3;
    for (std::size_t i = 0; i < ref.size(); ++i) {
        xyz.insert(xyz.end(), {ref.pos[i].x, ref.pos[i].y, ref.pos[i].z});
        val.push_back(ref.value[i]);
        other.push_back(-3.0);
        vec3.insert(vec3.end(), {3.0, 4.0, 0.0});
    }
    int n = 0;
    for (const char* fmt : {"ascii", "binary", "appended-raw", "appended-base64"})
        for (int z = 0; z < 2; ++z)
            for (int h64 = 0; h64 < 2; ++h64)
                for (int big = 0; big < 2; ++big) {
                    VtkEnc e{fmt, z == 1, h64 == 1, big == 1};
                    if (e.format == "ascii" && (z || h64 || big)) continue;
                    std::vector<std::byte> app;
                    std::string piece = "<Piece NumberOfPoints=\"37\" NumberOfVerts=\"0\">\n<PointData Scalars=\"rgba\">\n";
                    piece += vtk_array("Name=\"vec\" NumberOfComponents=\"3\"", vec3, false, e, app);
                    piece += vtk_array("Name=\"other\"", other, false, e, app);
                    piece += vtk_array("Name=\"f\"", val, true, e, app);
                    piece += "</PointData>\n<Points>\n" + vtk_array("NumberOfComponents=\"3\"", xyz, true, e, app) +
                             "</Points>\n</Piece>\n";
                    const std::string path = P(d, "p" + std::to_string(n++) + ".vtp");
                    spit(path, vtk_file("PolyData", {{"", piece}}, app, e, e.format == "appended-base64"));
                    INFO(path << " " << fmt << " zlib " << z << " h64 " << h64 << " big " << big);
                    const PointSet ps = read_point_set(path);
                    CHECK(ps.value_name == "other");  // Scalars names no array: first one-component array
                    PointSetOptions o;
                    o.value_name = "f";
                    const PointSet f = read_point_set(path, o);
                    require_same(f, ref);
                    o.value_name = "vec";  // a vector array chosen by name gives its norm
                    for (double v : read_point_set(path, o).value) CHECK(v == Approx(5.0));
                    o.value_name = "nope";
                    CHECK_THAT(error_of([&] { read_point_set(path, o); }), Catch::Contains("arrays: vec, other, f"));
                }
    CHECK(n == 25);
}

TEST_CASE("VTS: pieces and files become blocks with their extents' dims", "[scatter]") {
    TempDir d("ps-vts");
    VtkEnc e{"appended-raw", true, false, false};
    std::vector<std::string> paths;
    for (int f = 0; f < 2; ++f) {
        std::vector<std::byte> app;
        std::vector<std::pair<std::string, std::string>> pieces;
        const int nx = 3 + f, ny = 2, nz = 2;
        std::vector<double> xyz, val;
        for (int k = 0; k < nz; ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i) {
                    const double x = i * 0.5 + f, y = j * 2.0 + 0.1 * i, z = k * 0.25;  // curvilinear
                    xyz.insert(xyz.end(), {x, y, z});
                    val.push_back(fval(x, y, z));
                }
        const std::string ext = "0 " + std::to_string(nx - 1) + " 0 1 0 1";
        std::string piece = "<Piece Extent=\"" + ext + "\">\n<PointData Scalars=\"Density\">\n" +
                            vtk_array("Name=\"Density\"", val, true, e, app) + "</PointData>\n<Points>\n" +
                            vtk_array("NumberOfComponents=\"3\"", xyz, true, e, app) + "</Points>\n</Piece>\n";
        pieces.push_back({ext, piece});
        paths.push_back(P(d, "g" + std::to_string(f) + ".vts"));
        spit(paths.back(), vtk_file("StructuredGrid", pieces, app, e, false));
    }
    const PointSet ps = read_point_set(paths);
    REQUIRE(ps.blocks.size() == 2);
    CHECK(ps.blocks[0].dims == std::array<std::int64_t, 3>{3, 2, 2});
    CHECK(ps.blocks[1].dims == std::array<std::int64_t, 3>{4, 2, 2});
    CHECK(ps.blocks[1].first == 12);
    CHECK(ps.size() == 28);
    CHECK(ps.value_name == "Density");
    for (std::size_t i = 0; i < ps.size(); ++i) CHECK(ps.value[i] == fval(ps.pos[i].x, ps.pos[i].y, ps.pos[i].z));
    PointSetOptions o;
    o.merge_blocks = true;
    CHECK(read_point_set(paths, o).blocks.size() == 1);
    // a .vtp reader refuses a StructuredGrid
    std::filesystem::copy_file(paths[0], P(d, "wrong.vtp"));
    CHECK_THAT(error_of([&] { read_point_set(P(d, "wrong.vtp")); }), Catch::Contains("expected PolyData"));
}

// ---------------------------------------------------------------- raw records and .npy

TEST_CASE("raw float32 records: byte order detected, forced wrong order refused, trailing bytes", "[scatter]") {
    TempDir d("ps-raw");
    const PointSet ref = make_set(50, 1.0, {10, 20, 30});
    for (int big = 0; big < 2; ++big) {
        std::vector<std::byte> b;
        for (std::size_t i = 0; i < ref.size(); ++i) {
            put<float>(b, static_cast<float>(ref.pos[i].x), big);
            put<float>(b, static_cast<float>(ref.pos[i].y), big);
            put<float>(b, static_cast<float>(ref.pos[i].z), big);
            put<float>(b, static_cast<float>(ref.value[i]), big);
        }
        const std::string path = P(d, big ? "be.raw" : "le.raw");
        spit_bytes(path, b);
        REQUIRE(looks_like_point_set(path));
        const PointSet ps = read_point_set(path);
        require_same(ps, ref, 1e-4 * 30);
        PointSetOptions o;
        o.byte_order = big ? ByteOrder::little : ByteOrder::big;
        CHECK_THAT(error_of([&] { read_point_set(path, o); }), Catch::Contains(big ? "looks big-endian" : "looks little-endian"));
        b.resize(b.size() + 5);
        spit_bytes(path, b);
        CHECK_THAT(error_of([&] { read_point_set(path); }), Catch::Contains("5 trailing bytes"));
        o = {};
        o.allow_trailing = true;
        CHECK(read_point_set(path, o).size() == 50);
    }
    // a uint8 volume's bytes (a CT-like ramp with a blob) are not records: refused, naming the
    // likely mistake, unless the byte order is given
    std::vector<std::byte> vol;
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const int r2 = (x - 8) * (x - 8) + (y - 8) * (y - 8) + (z - 8) * (z - 8);
                vol.push_back(static_cast<std::byte>(r2 < 30 ? 200 - 3 * r2 : 10 + x + y));
            }
    const std::string path = P(d, "volume.raw");
    spit_bytes(path, vol);
    const std::string e = error_of([&] { read_point_set(path); });
    CHECK_THAT(e, Catch::Contains("volume.raw: not float32 x,y,z,value records"));
    CHECK_THAT(e, Catch::Contains("--dims"));
    PointSetOptions o;
    o.byte_order = ByteOrder::little;
    CHECK_NOTHROW(read_point_set(path, o));
}

TEST_CASE("npy: (N,3) positions only, (N,4) with values, Fortran order, trailing bytes", "[scatter]") {
    TempDir d("ps-npy");
    const PointSet ref = make_set(30, -4.0);
    auto npy = [&](int k, bool fortran, const char* descr) {
        std::string h = std::string("{'descr': '") + descr + "', 'fortran_order': " + (fortran ? "True" : "False") +
                        ", 'shape': (30, " + std::to_string(k) + "), }";
        while ((10 + h.size() + 1) % 64) h += ' ';
        h += '\n';
        std::vector<std::byte> b;
        for (char c : std::string("\x93NUMPY\x01\x00", 8)) b.push_back(static_cast<std::byte>(c));
        put<std::uint16_t>(b, static_cast<std::uint16_t>(h.size()), false);
        for (char c : h) b.push_back(static_cast<std::byte>(c));
        auto at = [&](std::size_t i, int c) { return c == 0 ? ref.pos[i].x : c == 1 ? ref.pos[i].y : c == 2 ? ref.pos[i].z : ref.value[i]; };
        const bool f8 = descr[2] == '8', big = descr[0] == '>';
        auto emit = [&](double v) { f8 ? put<double>(b, v, big) : put<float>(b, static_cast<float>(v), big); };
        if (fortran) for (int c = 0; c < k; ++c) for (std::size_t i = 0; i < 30; ++i) emit(at(i, c));
        else for (std::size_t i = 0; i < 30; ++i) for (int c = 0; c < k; ++c) emit(at(i, c));
        return b;
    };
    spit_bytes(P(d, "a.npy"), npy(3, false, "<f4"));
    const PointSet a = read_point_set(P(d, "a.npy"));
    CHECK_FALSE(a.has_values);
    CHECK(a.size() == 30);
    CHECK(a.pos[7].y == static_cast<float>(ref.pos[7].y));
    spit_bytes(P(d, "b.npy"), npy(4, true, ">f8"));
    require_same(read_point_set(P(d, "b.npy")), ref);
    auto t = npy(4, false, "<f8");
    t.push_back(std::byte{0});
    spit_bytes(P(d, "c.npy"), t);
    CHECK_THAT(error_of([&] { read_point_set(P(d, "c.npy")); }), Catch::Contains("1 trailing bytes"));
    spit_bytes(P(d, "d.npy"), npy(3, false, "<i4"));
    CHECK_THAT(error_of([&] { read_point_set(P(d, "d.npy")); }), Catch::Contains("unsupported .npy dtype"));
    // headers the fuzzer found (fuzz_npy): a key with nothing after its colon, a shape that is not a tuple;
    // each a one-line FormatError naming the file, never std::out_of_range
    auto with_header = [](const std::string& h) {
        std::string text = "\x93NUMPY";
        text += '\x01';
        text += '\x00';
        text += static_cast<char>(h.size() & 0xff);
        text += static_cast<char>(h.size() >> 8);
        text += h;
        std::vector<std::byte> b;
        for (char c : text) b.push_back(static_cast<std::byte>(c));
        return b;
    };
    spit_bytes(P(d, "e.npy"), with_header("{'descr': '<f4', 'fortran_order': False, 'shape':"));
    CHECK_THAT(error_of([&] { read_point_set(P(d, "e.npy")); }), Catch::Contains("e.npy: malformed .npy header"));
    spit_bytes(P(d, "f.npy"), with_header("{'descr': '<f4', 'fortran_order': False, 'shape': , }"));
    CHECK_THAT(error_of([&] { read_point_set(P(d, "f.npy")); }), Catch::Contains("is not a tuple"));
}

// ---------------------------------------------------------------- PLOT3D

namespace {

struct P3dSpec {
    bool big = true, records = false, multi = false, f64 = false, iblank = false, ascii = false;
    std::vector<std::array<int, 3>> dims{{4, 3, 2}};
};

// Node (i,j,k) of grid g: a sheared, offset grid; iblank 0 on every 5th point.
Vec3 node(int g, int i, int j, int k) { return {i * 0.5 + 0.1 * j + g * 10.0, j * 0.25 - 0.05 * k, k * 2.0 + 0.01 * i}; }
double q_of(int c, const Vec3& p) { return c == 0 ? 1.0 + 0.01 * p.x : c == 4 ? fval(p.x, p.y, p.z) : (c == 1 ? 3.0 : c == 2 ? 4.0 : 12.0) * (1.0 + 0.01 * p.x); }

struct Writer {
    const P3dSpec& s;
    std::vector<std::byte> b;
    std::string t;
    void i32(std::int64_t v) {
        if (s.ascii) t += std::to_string(v) + " ";
        else put<std::int32_t>(b, static_cast<std::int32_t>(v), s.big);
    }
    void real(double v) {
        if (s.ascii) {
            char c[40];
            std::snprintf(c, sizeof c, "%.17g ", v);
            t += c;
        } else if (s.f64) put<double>(b, v, s.big);
        else put<float>(b, static_cast<float>(v), s.big);
    }
    void mark(std::size_t n) {
        if (s.records && !s.ascii) put<std::int32_t>(b, static_cast<std::int32_t>(n), s.big);
    }
    int rs() const { return s.f64 ? 8 : 4; }
};

std::string header(Writer& w, int extra = -1) {
    const auto& s = w.s;
    if (s.multi) {
        w.mark(4), w.i32(static_cast<std::int64_t>(s.dims.size())), w.mark(4);
    }
    const int per = extra >= 0 ? 4 : 3;
    w.mark(4 * per * s.dims.size());
    for (const auto& d : s.dims) {
        w.i32(d[0]), w.i32(d[1]), w.i32(d[2]);
        if (extra >= 0) w.i32(extra);
    }
    w.mark(4 * per * s.dims.size());
    return "";
}

void write_p3d(const std::string& xyz, const std::string& q, const std::string& fn, const P3dSpec& s) {
    Writer w{s, {}, {}}, wq{s, {}, {}}, wf{s, {}, {}};
    header(w), header(wq), header(wf, 2);
    for (std::size_t g = 0; g < s.dims.size(); ++g) {
        const auto& d = s.dims[g];
        const std::size_t N = static_cast<std::size_t>(d[0]) * d[1] * d[2];
        std::vector<Vec3> p;
        for (int k = 0; k < d[2]; ++k)
            for (int j = 0; j < d[1]; ++j)
                for (int i = 0; i < d[0]; ++i) p.push_back(node(static_cast<int>(g), i, j, k));
        w.mark(3 * N * w.rs() + (s.iblank ? 4 * N : 0));
        for (const auto& v : p) w.real(v.x);
        for (const auto& v : p) w.real(v.y);
        for (const auto& v : p) w.real(v.z);
        if (s.iblank)
            for (std::size_t i = 0; i < N; ++i) w.i32(i % 5 == 0 ? 0 : 1);
        w.mark(3 * N * w.rs() + (s.iblank ? 4 * N : 0));
        wq.mark(4 * wq.rs());
        for (double v : {2.95, 0.0, 2.1e6, 1.39}) wq.real(v);
        wq.mark(4 * wq.rs());
        wq.mark(5 * N * wq.rs());
        for (int c = 0; c < 5; ++c)
            for (const auto& v : p) wq.real(q_of(c, v));
        wq.mark(5 * N * wq.rs());
        wf.mark(2 * N * wf.rs());
        for (const auto& v : p) wf.real(v.x + v.y);
        for (const auto& v : p) wf.real(fval(v.x, v.y, v.z));
        wf.mark(2 * N * wf.rs());
    }
    if (s.ascii) {
        spit(xyz, w.t), spit(q, wq.t), spit(fn, wf.t);
    } else {
        spit_bytes(xyz, w.b), spit_bytes(q, wq.b), spit_bytes(fn, wf.b);
    }
}

// Every point's position is a node of its block and the values follow the oracle.
void check_p3d(const PointSet& ps, const P3dSpec& s, int comp, bool function) {
    REQUIRE(ps.blocks.size() == s.dims.size());
    std::size_t total = 0, blanked = 0;
    for (std::size_t g = 0; g < s.dims.size(); ++g) {
        const auto& d = s.dims[g];
        CHECK(ps.blocks[g].dims == std::array<std::int64_t, 3>{d[0], d[1], d[2]});
        std::size_t idx = 0, out = ps.blocks[g].first;
        for (int k = 0; k < d[2]; ++k)
            for (int j = 0; j < d[1]; ++j)
                for (int i = 0; i < d[0]; ++i, ++idx) {
                    ++total;
                    if (s.iblank && idx % 5 == 0) {
                        ++blanked;
                        continue;
                    }
                    const Vec3 e = node(static_cast<int>(g), i, j, k);
                    const double tol = s.f64 || s.ascii ? 1e-12 : 1e-5 * (1 + std::fabs(e.x) + std::fabs(e.z));
                    REQUIRE(std::fabs(ps.pos[out].x - e.x) <= tol);
                    REQUIRE(std::fabs(ps.pos[out].y - e.y) <= tol);
                    REQUIRE(std::fabs(ps.pos[out].z - e.z) <= tol);
                    const double want = function ? fval(e.x, e.y, e.z) : comp == 5 ? 13.0 : q_of(comp, e);
                    REQUIRE(ps.value[out] == Approx(want).epsilon(1e-5));
                    ++out;
                }
    }
    CHECK(ps.size() + ps.dropped_blanked == total);
    CHECK(ps.dropped_blanked == blanked);
}

}  // namespace

TEST_CASE("PLOT3D: every layout (C/Fortran, LE/BE, single/multi, f32/f64, IBLANK, ASCII) is detected", "[scatter]") {
    TempDir d("ps-p3d");
    int n = 0;
    for (int ascii = 0; ascii < 2; ++ascii)
        for (int big = 0; big < 2; ++big)
            for (int rec = 0; rec < 2; ++rec)
                for (int multi = 0; multi < 2; ++multi)
                    for (int f64 = 0; f64 < 2; ++f64)
                        for (int ib = 0; ib < 2; ++ib) {
                            if (ascii && (big || rec || f64)) continue;
                            P3dSpec s;
                            s.ascii = ascii, s.big = big, s.records = rec, s.multi = multi, s.f64 = f64, s.iblank = ib;
                            if (multi) s.dims = {{4, 3, 2}, {2, 5, 3}};
                            const std::string base = P(d, "t" + std::to_string(n++));
                            write_p3d(base + "xyz.bin", base + "q.bin", base + ".f", s);
                            INFO(base << " ascii " << ascii << " big " << big << " records " << rec << " multi " << multi
                                      << " f64 " << f64 << " iblank " << ib);
                            REQUIRE(looks_like_point_set(base + "xyz.bin"));
                            check_p3d(read_point_set(base + "xyz.bin"), s, 0, false);  // sibling q, density
                            PointSetOptions o;
                            o.q_component = 4;
                            check_p3d(read_point_set(base + "xyz.bin", o), s, 4, false);
                            o.q_component = 5;  // speed = |rho u| / rho = 13
                            check_p3d(read_point_set(base + "xyz.bin", o), s, 5, false);
                            o = {};
                            o.function_file = base + ".f";
                            o.value_index = 1;
                            check_p3d(read_point_set(base + "xyz.bin", o), s, 0, true);
                        }
    CHECK(n == 36);
}

TEST_CASE("PLOT3D: bad input (dims disagree, trailing bytes, forced wrong byte order, truncation)", "[scatter]") {
    TempDir d("ps-p3d-bad");
    P3dSpec s;
    write_p3d(P(d, "axyz.bin"), P(d, "aq.bin"), P(d, "a.f"), s);
    P3dSpec s2 = s;
    s2.dims = {{4, 2, 3}};
    write_p3d(P(d, "bxyz.bin"), P(d, "bq.bin"), P(d, "b.f"), s2);
    PointSetOptions o;
    o.q_file = P(d, "bq.bin");
    CHECK_THAT(error_of([&] { read_point_set(P(d, "axyz.bin"), o); }), Catch::Contains("dims 4x2x3 disagree with the xyz dims 4x3x2"));
    // trailing bytes in the q file: refused by default, accepted with a note
    auto q = read_all((P(d, "aq.bin")));
    q.resize(q.size() + 484);
    spit_bytes(P(d, "aq.bin"), q);
    CHECK_THAT(error_of([&] { read_point_set(P(d, "axyz.bin")); }), Catch::Contains("484 trailing bytes"));
    o = {};
    o.allow_trailing = true;
    const PointSetInfo info = probe_point_set(P(d, "axyz.bin"), o);
    check_p3d(info.set, s, 0, false);
    bool noted = false;
    for (const auto& n : info.notes) noted = noted || n.find("484 bytes after the q data ignored") != std::string::npos;
    CHECK(noted);
    // forced little endian on a big-endian file: dims only make sense byte-swapped
    o = {};
    o.byte_order = ByteOrder::little;
    CHECK_THAT(error_of([&] { read_point_set(P(d, "axyz.bin"), o); }), Catch::Contains("looks big-endian"));
    // truncated xyz: its header's layout (big-endian float64 C, 4x3x2) needs 3 bytes more; read as
    // float32 it would leave bytes over, but the nearer explanation wins (the newcomer trial's
    // combxyz.bin cut short was "unrecognized volume format")
    auto x = read_all((P(d, "axyz.bin")));
    x.resize(x.size() - 3);
    spit_bytes(P(d, "cxyz.bin"), x);
    spit_bytes(P(d, "cq.bin"), read_all(P(d, "aq.bin")));  // the q file beside it names it a grid
    CHECK(error_of([&] { read_point_set(P(d, "cxyz.bin")); }) ==
          P(d, "cxyz.bin") + ": truncated PLOT3D xyz file: " + std::to_string(x.size()) +
              " bytes, the header (big-endian float32 C, single grid, 4x3x2) needs " + std::to_string(x.size() + 3));
    CHECK(looks_like_point_set(P(d, "cxyz.bin")));
    // float64 cut by 3 bytes also reads as float32 with bytes to spare: both readings are said,
    // the nearer first; --allow-trailing takes the one with bytes to spare, as the user asked
    P3dSpec s64 = s;
    s64.f64 = true;
    write_p3d(P(d, "exyz.bin"), P(d, "eq.bin"), P(d, "e.f"), s64);
    auto x64 = read_all(P(d, "exyz.bin"));
    x64.resize(x64.size() - 3);
    spit_bytes(P(d, "exyz.bin"), x64);
    CHECK_THAT(error_of([&] { read_point_set(P(d, "exyz.bin")); }),
               Catch::StartsWith(P(d, "exyz.bin") + ": truncated PLOT3D xyz file: " + std::to_string(x64.size()) + " bytes") &&
                   Catch::Contains("needs " + std::to_string(x64.size() + 3) + "; or ") &&
                   Catch::Contains("trailing bytes after the PLOT3D xyz data"));
    PointSetOptions at;
    at.allow_trailing = true;
    CHECK_NOTHROW(probe_point_set(P(d, "exyz.bin"), at));
    // the same bytes named as a grid by extension
    spit_bytes(P(d, "c.xyz"), x);
    CHECK_THAT(error_of([&] { read_point_set(P(d, "c.xyz")); }), Catch::Contains("truncated PLOT3D xyz file"));
    // cut to half: only the header's layout fits at all
    auto half = read_all((P(d, "axyz.bin")));
    half.resize(half.size() / 2);
    spit_bytes(P(d, "hxyz.bin"), half);
    spit_bytes(P(d, "hq.bin"), read_all(P(d, "aq.bin")));
    CHECK_THAT(error_of([&] { read_point_set(P(d, "hxyz.bin")); }), Catch::Contains("truncated PLOT3D xyz file"));
    // "xyz" in a .bin name without a q file beside it is no grid: float32 x,y,z,value records whose
    // first floats read as small big-endian ints (2.0 -> 64) stay points (review finding)
    std::vector<std::byte> rec;
    for (int i = 0; i < 4096; ++i)
        for (const float f : {2.0f, 2.0f, 2.0f, 1.0f + static_cast<float>(i)}) {
            const auto* b = reinterpret_cast<const std::byte*>(&f);
            rec.insert(rec.end(), b, b + 4);
        }
    spit_bytes(P(d, "cloud_xyzv.bin"), rec);
    CHECK(read_point_set(P(d, "cloud_xyzv.bin")).size() == 4096);
    // Fortran records cut short, whatever the name: the record markers vouch for the header
    P3dSpec f = s;
    f.records = true;
    f.multi = true;
    f.dims = {{4, 3, 2}, {2, 5, 3}};
    write_p3d(P(d, "fxyz.bin"), P(d, "fq.bin"), P(d, "f.f"), f);
    auto fr = read_all(P(d, "fxyz.bin"));
    fr.resize(fr.size() - 40);
    spit_bytes(P(d, "grid.bin"), fr);
    CHECK(looks_like_point_set(P(d, "grid.bin")));
    CHECK_THAT(error_of([&] { read_point_set(P(d, "grid.bin")); }),
               Catch::Contains("truncated PLOT3D xyz file") && Catch::Contains("Fortran-record, 2 grids"));
    spit_bytes(P(d, "dxyz.bin"), {});
    CHECK_THAT(error_of([&] { read_point_set(P(d, "dxyz.bin")); }), Catch::Contains("empty"));
    x.resize(10);
    spit_bytes(P(d, "e.xyz"), x);
    CHECK_THAT(error_of([&] { read_point_set(P(d, "e.xyz")); }), Catch::Contains("no layout"));
}

// ---------------------------------------------------------------- regular volumes

TEST_CASE("a regular volume is a point set: one point per voxel, block dims = volume dims", "[scatter]") {
    TempDir d("ps-vol");
    std::vector<std::byte> b;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::byte>(i + 4 * j + 12 * k));
    spit_bytes(P(d, "v_4x3x2_uint8.raw"), b);
    CHECK_FALSE(looks_like_point_set(P(d, "v_4x3x2_uint8.raw")));
    const PointSet ps = read_point_set(P(d, "v_4x3x2_uint8.raw"));
    REQUIRE(ps.size() == 24);
    CHECK(ps.blocks.at(0).dims == std::array<std::int64_t, 3>{4, 3, 2});
    for (std::size_t n = 0; n < 24; ++n) CHECK(ps.value[n] == ps.pos[n].x + 4 * ps.pos[n].y + 12 * ps.pos[n].z);
}

// ---------------------------------------------------------------- real data (SOURCES.md sections 2 and 3)

namespace {
std::string R(const std::string& rel) { return (meshless::test::shared_data() / rel).string(); }
}

TEST_CASE("real scattered data loads with the counts and ranges of SOURCES.md", "[scatter][real]") {
    if (!meshless::test::have_shared_data()) return;
    {
        const PointSet g = read_point_set(R("scattered/gravi.txt"));
        CHECK(g.size() == 2194);
        CHECK(g.value_range()[0] == Approx(-241.83));
        CHECK(g.value_range()[1] == Approx(111.295));
        CHECK(g.pos.back().x == 272318.921);  // UTM metres keep their millimetres
    }
    {
        const PointSetInfo p = probe_point_set(R("scattered/Particles.raw"));
        CHECK(p.format == "raw-float32");
        CHECK(p.set.size() == 197);
        CHECK(p.set.value_range()[0] == Approx(4));
        CHECK(p.set.value_range()[1] == Approx(9));
        CHECK(looks_like_point_set(R("scattered/Particles.raw")));
        bool big = false;
        for (const auto& n : p.notes) big = big || n.find("big endian (detected)") != std::string::npos;
        CHECK(big);
    }
    CHECK(read_point_set(R("scattered/sparsePoints.txt")).size() == 16);
    {
        const PointSet s = read_point_set(R("scattered/hyg_stars/stars.vtp"));
        CHECK(s.size() == 107857);
        CHECK(s.value_name == "lum");
        CHECK(s.value_range()[0] == Approx(2.9484922e-6));
        CHECK(s.value_range()[1] == Approx(67483.875));
        PointSetOptions o;
        o.value_name = "ci";
        CHECK(read_point_set(R("scattered/hyg_stars/stars.vtp"), o).value_name == "ci");
    }
    {
        const PointSet h = read_point_set(R("scattered/dark_matter_halo/halo_low_res.npy"));
        CHECK(h.size() == 32314);
        CHECK_FALSE(h.has_values);
        const auto b = h.bounds();
        CHECK(b[0].x == Approx(74.5).margin(0.1));
        CHECK(b[1].z == Approx(93.2).margin(0.1));
    }
    {
        const PointSet c = read_point_set(R("scattered/cactus.3337.pts"));
        CHECK(c.size() == 3337);
        CHECK_FALSE(c.has_values);
    }
}

TEST_CASE("real PLOT3D and VTS multiblock data loads with the dims and ranges of SOURCES.md", "[scatter][real]") {
    if (!meshless::test::have_shared_data()) return;
    {
        const PointSet c = read_point_set(R("plot3d/combxyz.bin"));  // sibling combq.bin
        CHECK(c.size() == 47025);
        CHECK(c.value_name == "density");
        CHECK(c.value_range()[0] == Approx(0.1978).margin(5e-5));
        CHECK(c.value_range()[1] == Approx(0.7104).margin(5e-5));
        const auto b = c.bounds();
        CHECK(b[0].x == Approx(0).margin(0.01));
        CHECK(b[1].x == Approx(16.51).margin(0.01));
        CHECK(b[0].y == Approx(-5.66).margin(0.01));
        CHECK(b[1].z == Approx(36.20).margin(0.01));
        CHECK(c.blocks.at(0).dims == std::array<std::int64_t, 3>{57, 33, 25});
        const PointSet m = read_point_set(R("plot3d/test.p3d"));  // names comb first
        require_same(m, c);
    }
    {
        CHECK_THAT(error_of([] { read_point_set(R("plot3d/bluntfinxyz.bin")); }), Catch::Contains("484 trailing bytes"));
        PointSetOptions o;
        o.allow_trailing = true;
        const PointSet b = read_point_set(R("plot3d/bluntfinxyz.bin"), o);
        CHECK(b.size() == 40960);
        CHECK(b.blocks.at(0).dims == std::array<std::int64_t, 3>{40, 32, 32});
        CHECK(b.value_range()[0] == Approx(0.1926).margin(5e-5));
        CHECK(b.value_range()[1] == Approx(4.9775).margin(5e-5));
    }
    {
        PointSetOptions o;
        o.q_component = 4;
        const PointSet p = read_point_set(R("plot3d/postxyz.bin"), o);
        CHECK(p.size() + p.dropped_blanked == 38u * 76 * 38);
        CHECK(p.blocks.at(0).dims == std::array<std::int64_t, 3>{38, 76, 38});
        CHECK(p.value_name == "energy");
        o.q_component = 0;
        const auto r = read_point_set(R("plot3d/postxyz.bin"), o).value_range();
        CHECK(r[0] == Approx(1.0));
        CHECK(r[1] == Approx(1.0));
    }
    {
        const PointSet f = read_point_set(R("plot3d/multi-bin.xyz"));
        const PointSet c = read_point_set(R("plot3d/multi-bin-C.xyz"));
        const PointSet a = read_point_set(R("plot3d/multi-ascii.xyz"));
        const PointSet m = read_point_set(R("plot3d/multi.p3d"));
        for (const PointSet* s : {&f, &c, &a, &m}) {
            REQUIRE(s->blocks.size() == 2);
            CHECK(s->blocks[0].dims == std::array<std::int64_t, 3>{8, 12, 12});
            CHECK(s->blocks[1].dims == std::array<std::int64_t, 3>{8, 12, 12});
            CHECK(s->size() + s->dropped_blanked == 2 * 8 * 12 * 12);
        }
        require_same(f, c);
        require_same(f, m);
        require_same(f, a, 1e-5);  // ASCII keeps 6 decimals
        PointSetOptions o;
        o.function_file = R("plot3d/multi-bin.f");
        const PointSet fn = read_point_set(R("plot3d/multi-bin.xyz"), o);
        CHECK(fn.size() == f.size());
        CHECK(fn.value_name == "function 0");
    }
    {
        std::vector<std::string> v = {R("plot3d/multicomb_0.vts"), R("plot3d/multicomb_1.vts"), R("plot3d/multicomb_2.vts")};
        const PointSet m = read_point_set(v);
        REQUIRE(m.blocks.size() == 3);
        CHECK(m.blocks[0].dims == std::array<std::int64_t, 3>{6, 12, 9});
        CHECK(m.blocks[1].dims == std::array<std::int64_t, 3>{8, 12, 9});
        CHECK(m.blocks[2].dims == std::array<std::int64_t, 3>{9, 12, 9});
        CHECK(m.value_name == "Density");
        CHECK(m.size() == (6 + 8 + 9) * 12 * 9u);
        const auto r = m.value_range();
        CHECK(r[0] >= 0.19);  // density of the combustor
        CHECK(r[1] <= 0.72);
    }
}

TEST_CASE("a header naming some coordinates but not all is refused", "[scatter]") {
    meshless::test::TempDir d("nozcol");
    {
        std::ofstream f(d / "a.csv");
        f << "x,y,value\n0,0,1\n1,0,2\n0,1,3\n1,1,4\n2,2,2\n";
    }
    CHECK_THROWS_WITH(meshless::read_point_set((d / "a.csv").string()), Catch::Contains("missing column z"));
}

TEST_CASE("plot3d meta: errors in the files a .p3d names name the .p3d too", "[scatter]") {
    TempDir d("p3d-named");
    spit(P(d, "m1.p3d"), "{\"filenames\":[{\"xyz\":\"missing.xyz\"}]}");
    const std::string e = error_of([&] { read_point_set(P(d, "m1.p3d")); });
    CHECK(e.rfind(P(d, "m1.p3d") + ": ", 0) == 0);
    CHECK_THAT(e, Catch::Contains("missing.xyz: cannot open"));
}
