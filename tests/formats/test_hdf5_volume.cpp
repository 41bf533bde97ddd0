// HDF5 datasets as volumes (formats/hdf5_volume.hpp), written here through libhdf5
// (tests/hdf5_test_data.hpp) against the oracle value(i, j, k) = (i + 5 j + 20 k) mod 113 on a 13 x 11 x 9
// grid: integer and float types of both byte orders, contiguous and chunked (chunks that do not
// divide the grid; deflate and shuffle), leading dimensions of size 1, geometry attributes, the
// dataset chosen by path, by --array or as the only volume, slab reads equal to the whole read;
// and one must-fail file per defect class.
#include <catch2/catch.hpp>

#include "error_of.hpp"
#include "formats/hdf5_volume.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

#if MESHLESS_HDF5
#include <zlib.h>

#include <fstream>

#include "hdf5_crash_input.hpp"
#include "hdf5_test_data.hpp"

using namespace meshless;
using meshless::test::error_of;
using meshless::test::Hdf5WriteOptions;
using meshless::test::TempDir;
using meshless::test::write_hdf5_volume;
using Catch::Matchers::Contains;

namespace {

constexpr std::int64_t NX = 13, NY = 11, NZ = 9;

void check_oracle(const Volume& v) {
    REQUIRE(v.grid.dims == std::array<std::int64_t, 3>{NX, NY, NZ});
    std::int64_t bad = 0;
    visit_samples(v.view(), [&](const auto* p) {
        for (std::int64_t k = 0; k < NZ; ++k)
            for (std::int64_t j = 0; j < NY; ++j)
                for (std::int64_t i = 0; i < NX; ++i)
                    if (static_cast<double>(p[i + NX * (j + NY * k)]) != test::hdf5_oracle(i, j, k)) ++bad;
    });
    CHECK(bad == 0);
}

}  // namespace

TEST_CASE("hdf5: every integer and float type of either byte order, contiguous and chunked, reads the oracle", "[formats][hdf5]") {
    const TempDir d("hdf5_types");
    struct Case {
        hid_t type;
        SampleType as;
    };
    const std::vector<Case> cases = {{H5T_STD_U8LE, SampleType::u8},   {H5T_STD_I8LE, SampleType::i16},   {H5T_STD_U16BE, SampleType::u16},
                                     {H5T_STD_I16LE, SampleType::i16}, {H5T_STD_U32BE, SampleType::f32},  {H5T_STD_I32LE, SampleType::f32},
                                     {H5T_STD_U64LE, SampleType::f32}, {H5T_STD_I64BE, SampleType::f32},  {H5T_IEEE_F32BE, SampleType::f32},
                                     {H5T_IEEE_F64LE, SampleType::f32}, {H5T_IEEE_F64BE, SampleType::f32}};
    int n = 0;
    for (const Case& c : cases) {
        for (int layout = 0; layout < 3; ++layout) {
            Hdf5WriteOptions o;
            o.file_type = c.type;
            if (layout > 0) o.chunk = {4, 5, 6};  // edge chunks along every axis
            if (layout == 2) o.deflate = 6, o.shuffle = true;
            const std::string f = (d.path / ("t" + std::to_string(n++) + ".h5")).string();
            write_hdf5_volume(f, "/g/v", NX, NY, NZ, o);
            INFO(f << " layout " << layout);
            const Volume v = read_volume(f);
            CHECK(v.type == c.as);
            check_oracle(v);
            const VolumeInfo i = probe_volume(f);
            CHECK(i.format == "hdf5");
            CHECK(i.grid.dims == v.grid.dims);
            CHECK(prove_volume(f).type == c.as);
        }
    }
}

TEST_CASE("hdf5: a growable dataset whose chunks are larger than its data reads the oracle", "[formats][hdf5]") {
    const TempDir d("hdf5_growable");
    const std::string f = (d.path / "g.h5").string();
    Hdf5WriteOptions o;
    o.growable = true;
    o.chunk = {16, 16, 16};
    o.deflate = 2;
    write_hdf5_volume(f, "/v", NX, NY, NZ, o);
    check_oracle(read_volume(f));
}

TEST_CASE("hdf5: slab reads of any depth equal the whole read, and the stream reader agrees", "[formats][hdf5]") {
    const TempDir d("hdf5_slabs");
    const std::string f = (d.path / "c.h5").string();
    Hdf5WriteOptions o;
    o.file_type = H5T_STD_I16BE;
    o.chunk = {4, 11, 13};
    o.deflate = 1;
    write_hdf5_volume(f, "/v", NX, NY, NZ, o);
    const Volume whole = read_volume(f);
    Hdf5Slices s(f, {});
    CHECK(s.row_depth() == 4);
    const std::size_t slice = static_cast<std::size_t>(NX * NY) * sample_size(s.type());
    for (std::int64_t depth : {1, 2, 3, 5, 9}) {
        std::vector<std::byte> got(static_cast<std::size_t>(NZ) * slice);
        for (std::int64_t z = 0; z < NZ; z += depth) s.read_slices(z, std::min(depth, NZ - z), got.data() + static_cast<std::size_t>(z) * slice);
        CHECK(std::memcmp(got.data(), whole.bytes.data(), got.size()) == 0);
    }
    CHECK_THROWS_AS(s.read_slices(8, 2, nullptr), InvalidArgument);
}

TEST_CASE("hdf5: the dataset by path, by --array, or the only volume, leading axes of size 1, geometry attributes", "[formats][hdf5]") {
    const TempDir d("hdf5_choice");
    const std::string f = (d.path / "two.h5").string();
    Hdf5WriteOptions a;
    a.attributes = {{"spacing", {0.5, 0.25, 2}}, {"origin", {-1, 2, 3}}};
    write_hdf5_volume(f, "/scans/ct", NX, NY, NZ, a);
    Hdf5WriteOptions b;
    b.leading = {1, 1};  // (t, c, z, y, x) of one time point and one channel
    b.attributes = {{"element_size_um", {4, 3, 2}}};  // z, y, x
    write_hdf5_volume(f, "/mic", NX, NY, NZ, b, /*append=*/true);
    const Volume ct = read_volume(f + ":/scans/ct");
    check_oracle(ct);
    CHECK(ct.grid.spacing == std::array<double, 3>{0.5, 0.25, 2});
    CHECK(ct.grid.origin == std::array<double, 3>{-1, 2, 3});
    RawOptions raw;
    raw.array = "mic";  // with or without the leading '/'
    const Volume mic = read_volume(f, raw);
    check_oracle(mic);
    CHECK(mic.grid.spacing == std::array<double, 3>{2, 3, 4});
    const VolumeInfo i = probe_volume(f + ":/mic");
    REQUIRE(i.arrays.size() == 2);
    CHECK(i.arrays[i.read_array].name == "/mic");
    CHECK_THAT(error_of([&] { read_volume(f); }), Contains("holds 2 volumes (/mic, /scans/ct)") && Contains(":/PATH or with --array PATH"));
    raw.array = "/scans/ct";
    CHECK_THROWS_WITH(read_volume(f + ":/mic", raw), Contains("names the dataset /mic, --array another (/scans/ct)"));
    const std::string one = (d.path / "one.h5").string();
    write_hdf5_volume(one, "/deep/in/groups", NX, NY, NZ);
    RawOptions spacing;
    spacing.spacing = std::array<double, 3>{2, 2, 2};  // the file gives none: taken
    CHECK(read_volume(one, spacing).grid.spacing == std::array<double, 3>{2, 2, 2});
    CHECK(looks_like_volume(one));
    CHECK(looks_like_volume(one + ":/deep/in/groups"));
    CHECK(is_hdf5_input(one + ":/anything"));
    CHECK_FALSE(is_hdf5_input((d.path / "absent.h5").string()));
}

TEST_CASE("hdf5: must-fail files, one per defect class", "[formats][hdf5]") {
    const TempDir d("hdf5_bad");
    const auto p = [&](const char* name) { return (d.path / name).string(); };
    std::ofstream(p("text.h5")) << "not an HDF5 file at all\n";
    CHECK_THAT(error_of([&] { read_volume(p("text.h5")); }), Contains("text.h5: libhdf5 cannot open it") && Contains("signature"));
    // truncated
    write_hdf5_volume(p("whole.h5"), "/v", NX, NY, NZ);
    {
        std::ifstream in(p("whole.h5"), std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), {});
        std::ofstream(p("cut.h5"), std::ios::binary) << bytes.substr(0, bytes.size() - 100);
    }
    CHECK_THAT(error_of([&] { read_volume(p("cut.h5")); }), Contains("cut.h5: libhdf5 cannot open it") && Contains("truncated"));
    // no such dataset, a group, a path without '/'-rooted components
    CHECK_THAT(error_of([&] { read_volume(p("whole.h5") + ":/w"); }), Contains("no object named '/w' in the file"));
    write_hdf5_volume(p("group.h5"), "/g/v", NX, NY, NZ);
    CHECK_THAT(error_of([&] { read_volume(p("group.h5") + ":/g"); }), Contains(":/g: is a group, not a dataset"));
    // not a volume: 2-D, a leading axis of 2, one sample along an axis
    Hdf5WriteOptions lead;
    lead.leading = {2};
    write_hdf5_volume(p("4d.h5"), "/v", NX, NY, NZ, lead);
    CHECK_THAT(error_of([&] { read_volume(p("4d.h5") + ":/v"); }), Contains("shape (2, 9, 11, 13) is not a volume"));
    write_hdf5_volume(p("flat.h5"), "/v", NX, NY, 1);
    CHECK_THAT(error_of([&] { read_volume(p("flat.h5") + ":/v"); }), Contains("every axis needs at least 2 samples"));
    CHECK_THAT(error_of([&] { read_volume(p("4d.h5")); }), Contains("no numeric dataset of 3 dimensions"));
    // a type the tool does not read
    test::write_hdf5_strings(p("strings.h5"));
    CHECK_THAT(error_of([&] { read_volume(p("strings.h5") + ":/v"); }), Contains("type string is not read"));
    // references out of the file: external raw data, an external link
    std::ofstream(p("outside.raw")) << "12345678";
    test::write_hdf5_external_data(p("ext.h5"), p("outside.raw"));
    CHECK_THAT(error_of([&] { read_volume(p("ext.h5") + ":/v"); }), Contains("external file(s): refused"));
    test::write_hdf5_external_link(p("link.h5"), p("whole.h5"));
    CHECK_THAT(error_of([&] { read_volume(p("link.h5") + ":/v"); }), Contains("external or user-defined link to another file: refused"));
    // a filter this libhdf5 cannot decode
    test::write_hdf5_unavailable_filter(p("blosc.h5"));
    CHECK_THAT(error_of([&] { read_volume(p("blosc.h5") + ":/v"); }), Contains("filter 32001") && Contains("cannot decode"));
    // bad geometry attributes: two values, a NaN, samples beyond the float32 range
    Hdf5WriteOptions two;
    two.attributes = {{"spacing", {1, 2}}};
    write_hdf5_volume(p("two.h5"), "/v", NX, NY, NZ, two);
    CHECK_THAT(error_of([&] { read_volume(p("two.h5")); }), Contains("attribute 'spacing': expected 3 numbers, got 2 values"));
    Hdf5WriteOptions nan;
    nan.attributes = {{"origin", {0, std::nan(""), 0}}};
    write_hdf5_volume(p("nan.h5"), "/v", NX, NY, NZ, nan);
    CHECK_THAT(error_of([&] { read_volume(p("nan.h5")); }), Contains("attribute 'origin': nan is not a finite number"));
    Hdf5WriteOptions far;
    far.attributes = {{"spacing", {1e308, 1, 1}}};
    write_hdf5_volume(p("far.h5"), "/v", NX, NY, NZ, far);
    CHECK_THAT(error_of([&] { read_volume(p("far.h5")); }), Contains("far.h5:/v") && Contains("float32 range"));
    // a corrupt deflate chunk: the chunk's bytes overwritten
    Hdf5WriteOptions z;
    z.chunk = {NZ, NY, NX};
    z.deflate = 9;
    write_hdf5_volume(p("z.h5"), "/v", NX, NY, NZ, z);
    {
        std::fstream io(p("z.h5"), std::ios::in | std::ios::out | std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(io)), {});
        const std::size_t at = bytes.find(std::string("\x78\xda", 2));  // the zlib stream of the chunk (level 9)
        REQUIRE(at != std::string::npos);
        io.seekp(static_cast<std::streamoff>(at + 2));
        io.write("\xff\xff\xff\xff\xff\xff\xff\xff", 8);
    }
    CHECK_THAT(error_of([&] { read_volume(p("z.h5")); }), Contains("z.h5:/v: chunk at (0, 0, 0): corrupt compressed data"));
    CHECK_THAT(error_of([&] { prove_volume(p("z.h5")); }), Contains("z.h5:/v: chunk at (0, 0, 0): corrupt compressed data"));
    // a chunk that inflates to fewer bytes than its size (libhdf5 1.10 would copy past its buffer)
    Hdf5WriteOptions half;
    half.chunk = {NZ, NY, NX};
    half.deflate = 1;
    write_hdf5_volume(p("half.h5"), "/v", NX, NY, NZ, half);
    {
        // the chunk's stream replaced by one of half its size, same stored length (zlib of zeros, padded)
        std::fstream io(p("half.h5"), std::ios::in | std::ios::out | std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(io)), {});
        const std::size_t at = bytes.find(std::string("\x78\x01", 2));
        REQUIRE(at != std::string::npos);
        const std::vector<unsigned char> zeros(static_cast<std::size_t>(NX * NY * NZ / 2), 0);
        uLongf n = compressBound(static_cast<uLong>(zeros.size()));
        std::vector<unsigned char> z(n);
        REQUIRE(compress2(z.data(), &n, zeros.data(), static_cast<uLong>(zeros.size()), 1) == Z_OK);
        io.seekp(static_cast<std::streamoff>(at));
        io.write(reinterpret_cast<const char*>(z.data()), static_cast<std::streamsize>(n));
    }
    CHECK_THAT(error_of([&] { read_volume(p("half.h5")); }), Contains("half.h5:/v: chunk at (0, 0, 0)"));
}

TEST_CASE("hdf5: a file on which libhdf5 itself crashes is refused, and this process survives", "[formats][hdf5]") {
    const TempDir d("hdf5_crash");
    const std::string f = (d.path / "crash.h5").string();
    std::ofstream(f, std::ios::binary).write(reinterpret_cast<const char*>(test::kHdf5CrashInput), sizeof test::kHdf5CrashInput);
    // libhdf5 1.10.8 crashes parsing it (in the child that parses every file first): refused in one
    // line; a libhdf5 that refuses it itself gives its own message, a FormatError too
    const std::string e = error_of([&] { read_volume(f); });
    CHECK_THAT(e, Contains("crash.h5"));
    CHECK(e.find('\n') == std::string::npos);
    CHECK_THROWS_AS(probe_volume(f), FormatError);
    CHECK_THROWS_AS(prove_volume(f), FormatError);
}

#else

TEST_CASE("hdf5: a build without libhdf5 refuses HDF5 files in one line", "[formats][hdf5]") {
    const meshless::test::TempDir d("hdf5_none");
    const std::string f = (d.path / "x.h5").string();
    std::ofstream(f) << "\x89HDF\r\n\x1a\n";
    CHECK_THAT(meshless::test::error_of([&] { meshless::read_volume(f); }), Catch::Matchers::Contains("this build has no HDF5 reader"));
}

#endif
