// NumPy .npy 3-D arrays as volumes (formats/npy_volume.hpp, formats/npy_header.hpp): every dtype the
// reader takes in both byte orders and both memory orders, written here byte by byte, against the
// analytic oracle value(i, j, k) = i + 5 j + 20 k; the mapped read; --spacing; the dispatch between
// 3-D volumes and 2-D point sets; files written by NumPy's own np.save (when /usr/bin/python3 imports
// numpy); and one must-fail file per defect class (bad magic, a header longer than the file,
// shape x itemsize overflowing, data shorter and longer than the shape, unsupported and object
// dtypes, a 2-D array read as a volume, an empty axis).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "error_of.hpp"
#include "format_test_util.hpp"
#include "formats/npy_header.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "npy_test_data.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::error_of;
using meshless::test::npy_prefix;
using meshless::test::TempDir;

namespace {

constexpr int NX = 5, NY = 4, NZ = 3;
double oracle(int i, int j, int k) { return i + 5 * j + 20 * k; }

template <class T>
std::string encode(T v, bool big) {
    std::string s(sizeof(T), '\0');
    std::memcpy(s.data(), &v, sizeof(T));
    if (big) std::reverse(s.begin(), s.end());
    return s;
}

std::string sample(const std::string& code, double v, bool big) {
    if (code == "u1") return encode<std::uint8_t>(static_cast<std::uint8_t>(v), big);
    if (code == "i1") return encode<std::int8_t>(static_cast<std::int8_t>(v), big);
    if (code == "u2") return encode<std::uint16_t>(static_cast<std::uint16_t>(v), big);
    if (code == "i2") return encode<std::int16_t>(static_cast<std::int16_t>(v), big);
    if (code == "u4") return encode<std::uint32_t>(static_cast<std::uint32_t>(v), big);
    if (code == "i4") return encode<std::int32_t>(static_cast<std::int32_t>(v), big);
    if (code == "f4") return encode<float>(static_cast<float>(v), big);
    return encode<double>(v, big);
}

// The oracle volume as np.save writes it: C order shape (NZ, NY, NX), or Fortran order (NX, NY, NZ).
std::string npy_volume(const std::string& code, bool big, bool fortran) {
    const std::string order = code[0] == 'u' && code[1] == '1' ? "|" : code[0] == 'i' && code[1] == '1' ? "|" : big ? ">" : "<";
    const std::string shape = fortran ? "(5, 4, 3)" : "(3, 4, 5)";
    std::string out = npy_prefix("{'descr': '" + order + code + "', 'fortran_order': " + (fortran ? "True" : "False") +
                                 ", 'shape': " + shape + ", }");
    for (int k = 0; k < NZ; ++k)  // x fastest in both orders
        for (int j = 0; j < NY; ++j)
            for (int i = 0; i < NX; ++i) out += sample(code, oracle(i, j, k), big);
    return out;
}

std::string P(const TempDir& d, const std::string& n) { return (d / n).string(); }

}  // namespace

TEST_CASE(".npy volumes: every dtype, both byte orders, C and Fortran order, the oracle's values", "[npy][volume]") {
    TempDir d("npy-volume");
    for (const char* code : {"u1", "i1", "u2", "i2", "u4", "i4", "f4", "f8"})
        for (int big = 0; big < 2; ++big)
            for (int fortran = 0; fortran < 2; ++fortran) {
                const std::string path = P(d, std::string(code) + (big ? "b" : "l") + (fortran ? "f" : "c") + ".npy");
                meshless::test::write_file(path, npy_volume(code, big, fortran));
                INFO(path);
                CHECK(looks_like_volume(path));
                CHECK_FALSE(looks_like_point_set(path));
                const VolumeInfo vi = probe_volume(path);
                CHECK(vi.format == "npy");
                CHECK(vi.grid.dims == std::array<std::int64_t, 3>{NX, NY, NZ});
                // the file maps when its dtype is a native sample type in host order
                const std::string c = code;
                CHECK(vi.maps == ((!big || c == "u1") && (c == "u1" || c == "u2" || c == "i2" || c == "f4")));  // u1: no byte order
                for (const Volume& v : {read_volume(path), map_volume(path)}) {
                    REQUIRE(v.grid.dims == std::array<std::int64_t, 3>{NX, NY, NZ});
                    CHECK(v.grid.spacing == std::array<double, 3>{1, 1, 1});
                    CHECK(v.grid.origin == std::array<double, 3>{0, 0, 0});
                    const VolumeView view = v.view();
                    for (int k = 0; k < NZ; ++k)
                        for (int j = 0; j < NY; ++j)
                            for (int i = 0; i < NX; ++i) REQUIRE(view.at(i, j, k) == oracle(i, j, k));
                }
                (void)prove_volume(path);
            }
    // --spacing (RawOptions::spacing) gives the geometry the file lacks
    RawOptions raw;
    raw.spacing = std::array<double, 3>{0.5, 2, 3};
    CHECK(read_volume(P(d, "f4lc.npy"), raw).grid.spacing == std::array<double, 3>{0.5, 2, 3});
    // a 3-D .npy read as a point set: one point per voxel, at the voxel's position
    const PointSet ps = read_point_set(P(d, "u2lc.npy"));
    REQUIRE(ps.size() == static_cast<std::size_t>(NX * NY * NZ));
    CHECK(ps.pos[NX + 2].x == 2);
    CHECK(ps.pos[NX + 2].y == 1);
    CHECK(ps.value[NX + 2] == oracle(2, 1, 0));
}

TEST_CASE(".npy: a 2-D array stays a point set, a 3-D one is a volume (the dispatch by dimensions)", "[npy][volume]") {
    TempDir d("npy-dispatch");
    std::string pts = npy_prefix("{'descr': '<f4', 'fortran_order': False, 'shape': (4, 4), }");
    for (int i = 0; i < 16; ++i) pts += encode<float>(static_cast<float>(i), false);
    meshless::test::write_file(P(d, "p.npy"), pts);
    CHECK(npy_ndim(P(d, "p.npy")) == 2);
    CHECK(looks_like_point_set(P(d, "p.npy")));
    CHECK_FALSE(looks_like_volume(P(d, "p.npy")));
    CHECK(read_point_set(P(d, "p.npy")).size() == 4);
    CHECK(point_set_format(P(d, "p.npy")) == "npy");
    CHECK_THAT(error_of([&] { read_volume(P(d, "p.npy")); }), Catch::Contains("p.npy: .npy shape (4, 4) is not a volume"));
    meshless::test::write_file(P(d, "v.npy"), npy_volume("u1", false, false));
    CHECK(point_set_format(P(d, "v.npy")) == "volume");
}

TEST_CASE(".npy written by NumPy's np.save: C order, Fortran order, big endian", "[npy][volume]") {
    if (std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") != 0) {
        WARN("numpy not importable by /usr/bin/python3: np.save files not tested");
        return;
    }
    TempDir d("npy-numpy");
    const std::string script =
        "import numpy as np, sys\n"
        "k, j, i = np.meshgrid(np.arange(3), np.arange(4), np.arange(5), indexing='ij')\n"
        "v = (i + 5 * j + 20 * k)\n"
        "np.save(sys.argv[1] + '/c.npy', v.astype(np.int16))\n"
        "np.save(sys.argv[1] + '/f.npy', np.asfortranarray(v.astype(np.float32).transpose()))\n"
        "np.save(sys.argv[1] + '/b.npy', v.astype('>f8'))\n";
    meshless::test::write_file(P(d, "w.py"), script);
    REQUIRE(std::system(("/usr/bin/python3 '" + P(d, "w.py") + "' '" + d.path.string() + "'").c_str()) == 0);
    for (const char* name : {"c.npy", "f.npy", "b.npy"}) {
        INFO(name);
        const Volume v = map_volume(P(d, name));
        REQUIRE(v.grid.dims == std::array<std::int64_t, 3>{NX, NY, NZ});
        const VolumeView view = v.view();
        for (int k = 0; k < NZ; ++k)
            for (int j = 0; j < NY; ++j)
                for (int i = 0; i < NX; ++i) REQUIRE(view.at(i, j, k) == oracle(i, j, k));
    }
    CHECK(probe_volume(P(d, "c.npy")).maps);
    CHECK(probe_volume(P(d, "f.npy")).maps);
}

TEST_CASE(".npy volume must-fail: one file per defect class, one line naming the file", "[npy][volume]") {
    TempDir d("npy-bad");
    const std::string good = npy_volume("f4", false, false);
    auto bad = [&](const std::string& name, const std::string& bytes, const std::string& expect) {
        const std::string path = P(d, name);
        meshless::test::write_file(path, bytes);
        for (int pass = 0; pass < 3; ++pass) {
            const std::string m = error_of<FormatError, IoError>([&] {
                if (pass == 0) (void)read_volume(path);
                if (pass == 1) (void)map_volume(path);
                if (pass == 2) (void)prove_volume(path);
            });
            INFO(name << " pass " << pass << ": " << m);
            CHECK(m.rfind(path + ": ", 0) == 0);
            CHECK(m.find('\n') == std::string::npos);
            CHECK_THAT(m, Catch::Contains(expect));
        }
    };
    bad("magic.npy", "\x93NUMPX" + good.substr(6), "missing \\x93NUMPY magic");
    {
        std::string s = good.substr(0, 40);
        s[8] = '\xff';
        s[9] = '\x7f';
        bad("hlen.npy", s, "truncated .npy header");
    }
    bad("overflow.npy",
        npy_prefix("{'descr': '<f8', 'fortran_order': False, 'shape': (4294967296, 4294967296, 2), }") + std::string(64, '\0'),
        "overflow");
    bad("short.npy", good.substr(0, good.size() - 4), "expected 240 bytes after offset 128 for 5x4x3 float32, file has 364");
    bad("long.npy", good + "x", "file has 369");
    bad("complex.npy", npy_prefix("{'descr': '<c8', 'fortran_order': False, 'shape': (3, 4, 5), }"), "unsupported .npy dtype '<c8'");
    bad("object.npy", npy_prefix("{'descr': '|O', 'fortran_order': False, 'shape': (3, 4, 5), }"), "object array");
    bad("struct.npy", npy_prefix("{'descr': [('a', '<f4')], 'fortran_order': False, 'shape': (3, 4, 5), }"), "structured dtypes");
    bad("empty.npy", npy_prefix("{'descr': '<f4', 'fortran_order': False, 'shape': (3, 0, 5), }"), "has an empty axis");
    bad("fourd.npy", npy_prefix("{'descr': '<f4', 'fortran_order': False, 'shape': (1, 3, 4, 5), }"), "is not a volume");
    bad("version.npy", std::string("\x93NUMPY\x07\x00", 8) + good.substr(8), "unsupported .npy version 7");
}
