// The PLY codec (formats/ply.hpp). Oracles: write -> read round trips in all three encodings
// (values bit-identical, from files, memory and a FIFO), the same records through the wrappers
// (oriented points, point sets, meshes) in every encoding, the padded/patched header equal to the
// declared one, and one must-fail input per defect class (each message one line naming the input
// and the line or byte, bytes from the file escaped).
#include <catch2/catch.hpp>

#include "error_of.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <thread>

#include "formats/ply.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/ply_points.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::error_of;
using meshless::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}
void spit(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary | std::ios::trunc) << s; }

template <class T>
void put(std::vector<unsigned char>& b, T v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    b.insert(b.end(), p, p + sizeof(T));
}


std::span<const std::byte> as_bytes(const std::string& s) { return {reinterpret_cast<const std::byte*>(s.data()), s.size()}; }

/// A header exercising every type, and a face element with lists.
PlyHeader rich_header(PlyEncoding enc, std::uint64_t nv, std::uint64_t nf) {
    PlyHeader h;
    h.encoding = enc;
    h.comments = {"made by test_ply", "bounds_lo 0,0,0"};
    h.obj_info = {"an obj_info line"};
    PlyElement v{"vertex", nv, {}, 0};
    v.props = {{"x", StoredType::f32, false, StoredType::u8},     {"y", StoredType::f32, false, StoredType::u8},
               {"z", StoredType::f64, false, StoredType::u8},     {"value", StoredType::f64, false, StoredType::u8},
               {"flag", StoredType::u8, false, StoredType::u8},   {"c", StoredType::i8, false, StoredType::u8},
               {"s", StoredType::i16, false, StoredType::u8},     {"us", StoredType::u16, false, StoredType::u8},
               {"id", StoredType::i32, false, StoredType::u8},    {"u", StoredType::u32, false, StoredType::u8}};
    PlyElement f{"face", nf, {{"vertex_indices", StoredType::i32, true, StoredType::u8}, {"q", StoredType::f32, false, StoredType::u8}}, 0};
    h.elements = {v, f};
    return h;
}

struct Rich {
    std::vector<unsigned char> vbytes, fbytes;
    std::vector<std::vector<double>> vvals;  // per vertex, all properties
    std::vector<std::vector<double>> flists;
    std::vector<double> fq;
};

Rich rich_data(std::size_t nv, std::size_t nf) {
    Rich r;
    for (std::size_t i = 0; i < nv; ++i) {
        const float x = static_cast<float>(i) * 0.1f - 3.3f, y = std::nextafter(1.0f / (i + 1), 2.0f);
        const double z = 1e6 + i * 1e-7, value = -std::sqrt(static_cast<double>(i));
        const std::uint8_t flag = static_cast<std::uint8_t>(i * 37);
        const std::int8_t c = static_cast<std::int8_t>(-128 + (i % 256));
        const std::int16_t s = static_cast<std::int16_t>(i % 2 ? -32768 : 32767);
        const std::uint16_t us = static_cast<std::uint16_t>(65535 - i);
        const std::int32_t id = static_cast<std::int32_t>(i % 3 ? -2147483647 - 1 : 2147483647);
        const std::uint32_t u = 4294967295u - static_cast<std::uint32_t>(i);
        put(r.vbytes, x), put(r.vbytes, y), put(r.vbytes, z), put(r.vbytes, value), put(r.vbytes, flag), put(r.vbytes, c);
        put(r.vbytes, s), put(r.vbytes, us), put(r.vbytes, id), put(r.vbytes, u);
        r.vvals.push_back({x, y, z, value, double(flag), double(c), double(s), double(us), double(id), double(u)});
    }
    for (std::size_t f = 0; f < nf; ++f) {
        const std::uint8_t n = static_cast<std::uint8_t>(3 + f % 3);
        put(r.fbytes, n);
        std::vector<double> l;
        for (std::uint8_t k = 0; k < n; ++k) {
            const std::int32_t idx = static_cast<std::int32_t>((f + k) % nv);
            put(r.fbytes, idx);
            l.push_back(idx);
        }
        const float q = 0.25f * static_cast<float>(f);
        put(r.fbytes, q);
        r.flists.push_back(l);
        r.fq.push_back(q);
    }
    return r;
}

void check_rich(PlyReader& rd, const Rich& r) {
    REQUIRE(rd.header().elements.size() == 2);
    CHECK(rd.header().comments == std::vector<std::string>{"made by test_ply", "bounds_lo 0,0,0"});
    CHECK(rd.header().obj_info == std::vector<std::string>{"an obj_info line"});
    std::vector<double> vals;
    std::size_t i = 0;
    while (rd.element() == 0) {
        const std::size_t n = rd.read_values(vals, 7);  // pieces that do not divide the count
        for (std::size_t k = 0; k < n; ++k, ++i)
            for (std::size_t p = 0; p < 10; ++p) REQUIRE(vals[k * 10 + p] == r.vvals.at(i)[p]);
    }
    CHECK(i == r.vvals.size());
    PlyRecord rec;
    std::size_t f = 0;
    while (rd.read_record(rec)) {
        CHECK(rec.lists[0] == r.flists.at(f));
        CHECK(rec.values[1] == r.fq.at(f));
        ++f;
    }
    CHECK(f == r.fq.size());
    CHECK(rd.finish() == 0);
}

}  // namespace

TEST_CASE("PLY codec: write -> read round trips in ascii, little and big endian, every type", "[ply]") {
    TempDir d("ply-rt");
    const Rich r = rich_data(50, 20);
    for (PlyEncoding enc : {PlyEncoding::ascii, PlyEncoding::binary_little_endian, PlyEncoding::binary_big_endian}) {
        INFO("encoding " << int(enc));
        const std::string path = (d / "r.ply").string();
        {
            PlyWriter w(path, rich_header(enc, 50, 20), PlyCounts::declared);
            w.append(r.vbytes.data(), 10 * 38);  // a piece, then the rest
            w.append(r.vbytes.data() + 10 * 38, r.vbytes.size() - 10 * 38);
            w.append(r.fbytes.data(), r.fbytes.size());
            w.commit();
        }
        const std::string bytes = slurp(path);
        PlyReader from_file(path);
        check_rich(from_file, r);
        PlyReader from_memory("mem", as_bytes(bytes));
        check_rich(from_memory, r);
        // the header parses back to what was written
        const PlyHeader h = parse_ply_header(bytes, path);
        CHECK(format_ply_header(h, false) == bytes.substr(0, h.header_bytes));
        if (enc == PlyEncoding::binary_little_endian) {
            // little endian on this host: the body is the packed records as given
            CHECK(bytes.substr(h.header_bytes) == std::string(r.vbytes.begin(), r.vbytes.end()) + std::string(r.fbytes.begin(), r.fbytes.end()));
        }
        // skipping an element (lists included) reaches the same records
        PlyReader skip(path);
        skip.skip_to(1);
        PlyRecord rec;
        REQUIRE(skip.read_record(rec));
        CHECK(rec.lists[0] == r.flists[0]);
        skip.skip_to(2);
        CHECK(skip.finish() == 0);
    }
}

TEST_CASE("PLY codec: a FIFO (size unknown) is read as it streams", "[ply]") {
    TempDir d("ply-fifo");
    const Rich r = rich_data(3000, 500);  // more than one pipe buffer
    const std::string file = (d / "r.ply").string(), fifo = (d / "f.ply").string();
    {
        PlyWriter w(file, rich_header(PlyEncoding::binary_big_endian, 3000, 500), PlyCounts::declared);
        w.append(r.vbytes.data(), r.vbytes.size());
        w.append(r.fbytes.data(), r.fbytes.size());
        w.commit();
    }
    const std::string bytes = slurp(file);
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    auto feed = [&](std::string b) {
        return std::thread([fifo, b] { std::ofstream(fifo, std::ios::binary) << b; });
    };
    {
        std::thread t = feed(bytes);
        PlyReader rd(fifo);
        CHECK_FALSE(rd.size_known());
        check_rich(rd, r);
        t.join();
    }
    {  // cut mid-record: the count check cannot see it up front, the read does
        std::thread t = feed(bytes.substr(0, bytes.size() - 3));
        std::string e;
        try {
            PlyReader rd(fifo);
            rd.finish();
        } catch (const FormatError& x) {
            e = x.what();
        }
        t.join();
        CHECK_THAT(e, Catch::Contains(fifo + ": byte ") && Catch::Contains("truncated PLY body in element 'face'"));
    }
}

TEST_CASE("PLY codec: patched counts give the declared header's bytes", "[ply]") {
    TempDir d("ply-patch");
    const Rich r = rich_data(40, 0);
    PlyHeader h = rich_header(PlyEncoding::binary_little_endian, 40, 0);
    h.elements.pop_back();
    {
        PlyWriter w((d / "a.ply").string(), h, PlyCounts::patched);
        w.append(r.vbytes.data(), 38 * 13);
        w.append(r.vbytes.data() + 38 * 13, r.vbytes.size() - 38 * 13);
        CHECK(w.count(0) == 40);
        w.commit();
    }
    {
        PlyWriter w((d / "b.ply").string(), h, PlyCounts::declared_padded);
        w.append(r.vbytes.data(), r.vbytes.size());
        w.commit();
    }
    CHECK(slurp(d / "a.ply") == slurp(d / "b.ply"));
    CHECK_THAT(slurp(d / "a.ply"), Catch::Contains("element vertex 40\ncomment                  \nproperty float x\n"));
    PlyReader rd((d / "a.ply").string());
    CHECK(rd.header().comments.size() == 2);  // the padding comment is blank: dropped
    CHECK(rd.header().elements[0].count == 40);
    // declared counts are enforced
    {
        PlyWriter w((d / "c.ply").string(), h, PlyCounts::declared);
        w.append(r.vbytes.data(), 38);
        CHECK_THROWS_AS(w.commit(), std::logic_error);
        CHECK_THROWS_AS(w.append(r.vbytes.data(), r.vbytes.size()), std::logic_error);
        CHECK_THROWS_AS(w.append(r.vbytes.data(), 37), std::invalid_argument);
    }
    CHECK_FALSE(fs::exists(d / "c.ply"));
    CHECK_THROWS_AS(PlyWriter("-", h, PlyCounts::patched), IoError);
    // two elements, patched: next_element() moves on; the same bytes as declared up front
    const Rich r2 = rich_data(30, 12);
    {
        PlyWriter w((d / "e.ply").string(), rich_header(PlyEncoding::binary_big_endian, 0, 0), PlyCounts::patched);
        w.append(r2.vbytes.data(), r2.vbytes.size());
        w.next_element();
        w.append(r2.fbytes.data(), r2.fbytes.size());
        CHECK(w.count(0) == 30);
        CHECK(w.count(1) == 12);
        w.commit();
    }
    {
        PlyWriter w((d / "f.ply").string(), rich_header(PlyEncoding::binary_big_endian, 30, 12), PlyCounts::declared_padded);
        w.append(r2.vbytes.data(), r2.vbytes.size());
        w.append(r2.fbytes.data(), r2.fbytes.size());
        w.commit();
    }
    CHECK(slurp(d / "e.ply") == slurp(d / "f.ply"));
    PlyReader re((d / "e.ply").string());
    check_rich(re, r2);
}

TEST_CASE("PLY codec: oriented points, point sets and meshes in every encoding read the same", "[ply]") {
    TempDir d("ply-wrap");
    std::vector<PointRecord> pts(70000);  // more than one 65536-record piece
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const float f[8] = {float(i) * 0.5f, -float(i), 1.0f / float(i + 1), 0, 0.6f, 0.8f, 0.01f, float(i % 7)};
        std::memcpy(&pts[i], f, sizeof f);
    }
    write_ply_points((d / "le.ply").string(), pts, {"c"});
    const PlyHeader h = parse_ply_header(slurp(d / "le.ply"), "le.ply");
    Mesh m;
    m.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.5f, 0.5f, 1.5f};
    m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0.1f, 0.2f, 0.3f};
    m.tri = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    write_ply_mesh(m, (d / "mle.ply").string());
    const PlyHeader hm = parse_ply_header(slurp(d / "mle.ply"), "mle.ply");
    for (PlyEncoding enc : {PlyEncoding::ascii, PlyEncoding::binary_big_endian}) {
        INFO("encoding " << int(enc));
        PlyHeader h2 = h;
        h2.encoding = enc;
        {
            PlyWriter w((d / "p.ply").string(), h2, PlyCounts::declared);
            w.append(pts.data(), pts.size() * sizeof(PointRecord));
            w.commit();
        }
        const PlyPoints back = read_ply_points((d / "p.ply").string());  // the per-property path
        REQUIRE(back.points.size() == pts.size());
        CHECK(std::memcmp(back.points.data(), pts.data(), pts.size() * sizeof(PointRecord)) == 0);
        const PointSet ps = read_point_set((d / "p.ply").string());
        REQUIRE(ps.size() == pts.size());
        CHECK(ps.value_name == "value");
        for (std::size_t i = 0; i < pts.size(); ++i) {
            CHECK(ps.pos[i].x == pts[i].pos[0]);
            CHECK(ps.value[i] == pts[i].value);
        }
        PlyHeader hm2 = hm;
        hm2.encoding = enc;
        {
            std::vector<unsigned char> vn, f;  // per vertex: position, then normal
            for (std::size_t i = 0; i < 4; ++i) {
                for (int k = 0; k < 3; ++k) put(vn, m.xyz[3 * i + k]);
                for (int k = 0; k < 3; ++k) put(vn, m.normals[3 * i + k]);
            }
            for (std::size_t t = 0; t < 4; ++t) {
                put(f, std::uint8_t(3));
                for (int k = 0; k < 3; ++k) put(f, static_cast<std::int32_t>(m.tri[3 * t + k]));
            }
            PlyWriter w((d / "m.ply").string(), hm2, PlyCounts::declared);
            w.append(vn.data(), vn.size());
            w.append(f.data(), f.size());
            w.commit();
        }
        const Mesh mb = read_ply_mesh((d / "m.ply").string());
        CHECK(mb.xyz == m.xyz);
        CHECK(mb.normals == m.normals);
        CHECK(mb.tri == m.tri);
    }
}

TEST_CASE("PLY codec: one must-fail input per defect class", "[ply]") {
    const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
    const std::string le = "ply\nformat binary_little_endian 1.0\n";
    const std::string asc = "ply\nformat ascii 1.0\n";
    std::string rec12(12, '\0');
    struct Case {
        const char* what;
        std::string bytes;
        const char* message;
    };
    const Case cases[] = {
        {"empty", "", "not a PLY file"},
        {"bad magic", "plx\nformat ascii 1.0\nend_header\n", "not a PLY file"},
        {"binary garbage", std::string("\x89PNG\r\n\x1a\n", 8), "not a PLY file (missing 'ply' magic; starts with '\\x89PNG\\x0d"},
        {"unknown format", "ply\nformat binary_middle_endian 1.0\nend_header\n", "line 2: unknown PLY format 'binary_middle_endian'"},
        {"bad version", "ply\nformat ascii 2.0\nend_header\n", "unsupported PLY version '2.0'"},
        {"no format", "ply\nelement vertex 0\n" + xyz + "end_header\n", "no format line"},
        {"two formats", le + "format ascii 1.0\nend_header\n", "line 3: second PLY format line"},
        {"count overflow", le + "element vertex 18446744073709551615\n" + xyz + "end_header\n" + rec12,
         "line 3: PLY element 'vertex' count 18446744073709551615 x 12 bytes per record overflows"},
        {"count beyond uint64", le + "element vertex 18446744073709551616\n" + xyz + "end_header\n", "bad PLY element count"},
        {"negative count", le + "element vertex -1\n" + xyz + "end_header\n", "bad PLY element count '-1'"},
        {"count larger than the data", le + "element vertex 1000\n" + xyz + "end_header\n" + rec12 + rec12,
         "claims 1000 records (with the elements before it at least 12000 bytes) but only 24 bytes follow"},
        {"count over two elements", le + "element vertex 2\n" + xyz + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + rec12 + rec12,
         "PLY element 'face' claims 1 records"},
        {"ascii count larger than the data", asc + "element vertex 100\n" + xyz + "end_header\n1 2 3\n", "claims 100 records"},
        {"truncated binary body", le + "element vertex 2\n" + xyz + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                                      rec12 + rec12 + std::string("\x03\0\0\0\0", 5),
         "truncated PLY body in element 'face' at record 0 of 1"},
        {"truncated ascii body", asc + "element vertex 3\n" + xyz + "end_header\n1000000 2000000 3000000\n4 5 6\n",
         "truncated PLY body in element 'vertex' at record 2 of 3"},
        {"list longer than the data", le + "element face 1\nproperty list uint int vertex_indices\nend_header\n" + std::string("\xff\xff\xff\x0f", 4) + rec12,
         "truncated PLY body in element 'face'"},
        {"unsupported property type", asc + "element vertex 1\nproperty float128 x\nend_header\n1\n", "unknown PLY property type 'float128'"},
        {"64-bit integers", asc + "element vertex 1\nproperty int64 x\nend_header\n1\n", "unknown PLY property type 'int64'"},
        {"float list length", asc + "element face 1\nproperty list float int vertex_indices\nend_header\n1 1\n", "list length type must be an integer type"},
        {"property before element", asc + "property float x\nend_header\n", "line 3: PLY property before any element"},
        {"duplicate property", asc + "element vertex 1\nproperty float x\nproperty float x\nend_header\n1 1\n", "second property 'x'"},
        {"duplicate element", asc + "element vertex 0\nelement vertex 0\nend_header\n", "second PLY element named 'vertex'"},
        {"records without properties", asc + "element vertex 5\nend_header\n", "has 5 records but no properties"},
        {"unknown keyword, escaped", asc + "bogus\x01\xff line\nend_header\n", "line 3: malformed PLY header line 'bogus\\x01\\xff line'"},
        {"no end_header", asc + "element vertex 1\n" + xyz, "truncated PLY header (no end_header)"},
        {"header without end in 1 MiB", asc + std::string(kPlyMaxHeaderBytes, '\n') + "end_header\n",
         "no PLY end_header in the first 1048576 bytes"},
        {"ascii bad number", asc + "element vertex 1\n" + xyz + "end_header\n1 2 zz\n", "line 8: bad number 'zz' for property 'z'"},
        {"ascii integer out of range", asc + "element vertex 1\nproperty uchar red\nend_header\n300\n", "'300' is not a uchar (property 'red')"},
        {"ascii fraction for an integer", asc + "element vertex 1\nproperty int id\nend_header\n1.5\n", "'1.5' is not a int"},
        {"ascii too many values", asc + "element vertex 1\n" + xyz + "end_header\n1 2 3 4\n", "line 8: 4 values for a 'vertex' record, expected 3"},
        {"ascii too few values", asc + "element vertex 2\n" + xyz + "end_header\n10 20\n30 40 50\n", "line 8: 2 values for a 'vertex' record, more expected"},
        {"ascii list longer than the line", asc + "element face 1\nproperty list uchar int vertex_indices\nend_header\n4 1 2 3\n",
         "list of 4 items, the line has 3 values left"},
        {"ascii negative list length", asc + "element face 1\nproperty list char int vertex_indices\nend_header\n-1\n", "negative list length -1"},
        {"binary trailing bytes", le + "element vertex 1\n" + xyz + "end_header\n" + rec12 + "xx", "byte 127: 2 trailing bytes after the last PLY element"},
        {"ascii trailing text", asc + "element vertex 1\n" + xyz + "end_header\n1 2 3\n\n4\n", "line 10: unexpected '4\\x0a' after the last PLY element"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        const std::string e = error_of([&] {
            PlyReader r("in.ply", as_bytes(c.bytes));
            r.finish();
        });
        CHECK_THAT(e, Catch::StartsWith("in.ply: ") && Catch::Contains(c.message));
        CHECK(e.find('\n') == std::string::npos);
    }
}

TEST_CASE("PLY codec: the wrappers' own defects", "[ply]") {
    TempDir d("ply-wrap-bad");
    const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
    const std::string asc = "ply\nformat ascii 1.0\n";
    auto P = [&](const char* n) { return (d / n).string(); };
    // a list in a point element
    spit(d / "list.ply", asc + "element vertex 4\n" + xyz + "property list uchar float extra\nend_header\n" +
                             std::string("0 0 0 1 5\n1 0 0 1 5\n0 1 0 1 5\n0 0 1 1 5\n"));
    CHECK_THAT(error_of([&] { read_ply_points(P("list.ply")); }), Catch::Contains("list properties on PLY vertices are not supported"));
    CHECK_THAT(error_of([&] { read_point_set(P("list.ply")); }), Catch::Contains("list property 'extra' on PLY vertices"));
    // a missing required property
    spit(d / "noz.ply", asc + "element vertex 4\nproperty float x\nproperty float y\nend_header\n0 0\n1 0\n0 1\n1 1\n");
    CHECK_THAT(error_of([&] { read_ply_points(P("noz.ply")); }), Catch::Contains("noz.ply: line 3: PLY vertices have no x y z"));
    CHECK_THAT(error_of([&] { read_point_set(P("noz.ply")); }), Catch::Contains("no x y z"));
    CHECK_THAT(error_of([&] { read_ply_mesh(P("noz.ply")); }), Catch::Contains("noz.ply: line 3: PLY vertex element lacks x, y or z"));
    spit(d / "novertex.ply", asc + "element face 0\nproperty list uchar int vertex_indices\nend_header\n");
    CHECK_THAT(error_of([&] { read_ply_points(P("novertex.ply")); }), Catch::Contains("no vertex element"));
    // non-finite values where they are refused: strict point sets, mesh coordinates
    spit(d / "nan.ply", asc + "element vertex 6\n" + xyz + "property float value\nend_header\n" +
                            "0 0 0 1\n1 0 0 2\n0 1 0 nan\n0 0 1 4\n1 1 0 5\ninf 1 1 6\n");
    const PointSet ps = read_point_set(P("nan.ply"));
    CHECK(ps.size() == 4);
    CHECK(ps.dropped_nonfinite == 2);
    PointSetOptions strict;
    strict.strict = true;
    CHECK_THAT(error_of([&] { read_point_set(P("nan.ply"), strict); }), Catch::Contains("vertex 2: non-finite value"));
    spit(d / "nanmesh.ply", asc + "element vertex 3\n" + xyz + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                                "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
    CHECK_THAT(error_of([&] { read_ply_mesh(P("nanmesh.ply")); }), Catch::Contains("non-finite PLY vertex y"));
    // trailing bytes: refused by default, noted when allowed
    spit(d / "trail.ply", asc + "element vertex 4\n" + xyz + "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\nrest\n");
    CHECK_THAT(error_of([&] { read_point_set(P("trail.ply")); }), Catch::Contains("after the last PLY element"));
    PointSetOptions lax;
    lax.allow_trailing = true;
    const PointSetInfo info = probe_point_set(P("trail.ply"), lax);
    CHECK(info.set.size() == 4);
    bool noted = false;
    for (const auto& n : info.notes) noted = noted || n.find("trailing bytes ignored") != std::string::npos;
    CHECK(noted);
    // a directory and a missing file are environment errors
    CHECK_THROWS_AS(PlyReader(d.path.string()), IoError);
    CHECK_THROWS_AS(PlyReader(P("missing.ply")), IoError);
}

TEST_CASE("PLY codec: a parsed header formats back to text that parses to the same model", "[ply]") {
    // CRLF, tabs, stray \r and \v inside lines (a fuzz_ply finding: a comment ending in \r did not round-trip)
    const std::string text =
        "ply\r\nformat\tascii 1.0\r\ncomment  a comment\twith a tab \r\r\ncomment " + std::string("\x01\x00\r   \r\n", 8) +
        "obj_info o\v\r\nelement vertex 2\r\nproperty\tfloat x\r\r\nproperty list uchar int idx\r\nend_header\r\n";
    const PlyHeader h = parse_ply_header(text, "crlf.ply");
    REQUIRE(h.comments.size() == 2);
    CHECK(h.comments[0] == "a comment\twith a tab");
    CHECK(h.comments[1] == std::string("\x01\x00", 2));
    CHECK(h.obj_info == std::vector<std::string>{"o"});
    REQUIRE(h.elements.size() == 1);
    CHECK(h.elements[0].props[0].name == "x");
    CHECK(h.elements[0].props[1].is_list);
    CHECK(h.header_bytes == text.size());
    const PlyHeader again = parse_ply_header(format_ply_header(h, false), "again");
    CHECK(again.comments == h.comments);
    CHECK(again.obj_info == h.obj_info);
    CHECK(format_ply_header(again, true) == format_ply_header(h, true));

    // a comment a producer made from a file name with line breaks stays one line
    PlyHeader made = h;
    made.comments = {"source a\nb\rc.raw"};
    made.obj_info = {"x\ny"};
    const std::string t = format_ply_header(made, false);
    CHECK_THAT(t, Catch::Contains("comment source a\\x0ab\rc.raw\nobj_info x\\x0ay\n"));
    const PlyHeader back = parse_ply_header(t, "made");
    CHECK(back.comments == std::vector<std::string>{"source a\\x0ab\rc.raw"});  // (a CR stays inside its line)
    // a parsed comment holding a CR formats back to the same text (fuzz_ply's finding)
    const std::string cr = "ply\nformat ascii 1.0\ncomment seed \r" + std::string(3, '\0') + "x\nelement vertex 0\nend_header\n";
    const PlyHeader hc = parse_ply_header(cr, "cr");
    CHECK(parse_ply_header(format_ply_header(hc, false), "again").comments == hc.comments);
    CHECK(back.elements.size() == 1);
}
