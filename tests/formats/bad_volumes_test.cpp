// Must-fail inputs, each generated in a TempDir: every failure is a FormatError (bad content)
// or IoError (cannot open), with a one-line message that starts with the offending path.
#include <catch2/catch.hpp>

#include <filesystem>
#include <limits>

#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "tests/formats/format_test_util.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

enum class Kind { format, io };

// Reads (and probes, when `probe_too`) and checks the exception kind, the message's first
// characters (the path) and a fragment of the text.
void expect_fail(const std::string& path, Kind kind, const std::string& fragment, const std::string& starts_with = "",
                 bool probe_too = true) {
    INFO("reading " << path);
    const std::string prefix = starts_with.empty() ? path : starts_with;
    for (int pass = 0; pass < (probe_too ? 2 : 1); ++pass) {
        std::string msg;
        bool right_kind = false;
        try {
            if (pass == 0)
                (void)read_volume(path);
            else
                (void)probe_volume(path);
        } catch (const FormatError& e) {
            msg = e.what();
            right_kind = kind == Kind::format;
        } catch (const IoError& e) {
            msg = e.what();
            right_kind = kind == Kind::io;
        }
        INFO((pass == 0 ? "read_volume: " : "probe_volume: ") << msg);
        CHECK(right_kind);
        CHECK(msg.rfind(prefix, 0) == 0);
        CHECK(msg.find('\n') == std::string::npos);
        CHECK(msg.find(fragment) != std::string::npos);
    }
}

const std::string kNrrdHead = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n";

}  // namespace

TEST_CASE("bad volumes: size mismatches and truncation", "[formats]") {
    TempDir dir("fmt-bad1");
    const std::string raw = (dir / "vol_64x64x64_uint8.raw").string();
    write_file(raw, "", std::vector<std::byte>(1000));
    expect_fail(raw, Kind::format, "expected 262144 bytes for 64x64x64 uint8, file has 1000", raw, false);
    const std::string big = (dir / "vol_4x4x4_int16.raw").string();  // too long is also wrong for raw
    write_file(big, "", std::vector<std::byte>(129));
    expect_fail(big, Kind::format, "expected 128 bytes for 4x4x4 int16, file has 129", big, false);

    const std::string nrrd = (dir / "trunc.nrrd").string();
    write_file(nrrd, kNrrdHead + "\n", std::vector<std::byte>(40));
    expect_fail(nrrd, Kind::format, "expected 64 bytes", nrrd, false);

    const std::string gz = (dir / "trunc_gz.nrrd").string();
    auto z = deflate_bytes(std::vector<std::byte>(64, std::byte{7}), true);
    z.resize(z.size() / 2);
    write_file(gz, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\n\n", z);
    expect_fail(gz, Kind::format, "compressed", gz, false);

    const std::string gzshort = (dir / "short_gz.nrrd").string();  // complete gzip stream, too little data
    write_file(gzshort, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\n\n",
               deflate_bytes(std::vector<std::byte>(10), true));
    expect_fail(gzshort, Kind::format, "ends", gzshort, false);

    const std::string vtk = (dir / "trunc.vtk").string();
    write_file(vtk, "# vtk DataFile Version 3.0\nx\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 4 4 4\nPOINT_DATA 64\n"
                    "SCALARS s short\nLOOKUP_TABLE default\n",
               std::vector<std::byte>(100));
    expect_fail(vtk, Kind::format, "expected 128 bytes", vtk, false);

    const std::string asc = (dir / "short_ascii.vtk").string();
    write_file(asc, "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nPOINT_DATA 8\n"
                    "SCALARS s float\n1 2 3 4 5\n");
    expect_fail(asc, Kind::format, "header claims 8 ascii values for 2x2x2", asc, false);

    const std::string nii = (dir / "trunc.nii.gz").string();
    {
        std::vector<std::byte> h;
        put_value<std::int32_t>(h, 348, false);
        h.resize(40);
        for (short d : {3, 8, 8, 8, 1, 1, 1, 1}) put_value<std::int16_t>(h, d, false);
        h.resize(70);
        put_value<std::int16_t>(h, 2, false);
        h.resize(108);
        put_value<float>(h, 352, false);
        h.resize(344);
        for (char c : {'n', '+', '1', '\0'}) h.push_back(std::byte(c));
        h.resize(352 + 100);  // 512 needed
        write_file(nii, "", deflate_bytes(h, true));
    }
    expect_fail(nii, Kind::format, "ends after", nii, false);

    const std::string slc = (dir / "trunc.slc").string();
    {
        static const char text[] = "11111\n2 2 2 8\n1 1 1\n0 0 0 1\n0 0 X6 X\x84\x01\x02\x03\x04\x00" "100 X\x01";
        write_file(slc, std::string(text, sizeof text - 1));
    }
    expect_fail(slc, Kind::format, "truncated: slice 1", slc, false);

    const std::string vti = (dir / "trunc.vti").string();
    write_file(vti, "<VTKFile type=\"ImageData\" header_type=\"UInt32\"><ImageData WholeExtent=\"0 3 0 3 0 3\"><Piece "
                    "Extent=\"0 3 0 3 0 3\"><PointData><DataArray type=\"UInt8\" Name=\"a\" format=\"binary\">QAAAAAECAwQ="
                    "</DataArray></PointData></Piece></ImageData></VTKFile>");
    expect_fail(vti, Kind::format, "truncated DataArray", vti, false);

    const std::string dims = (dir / "dims.vti").string();  // header says 2 bytes, grid needs 64
    write_file(dims, "<VTKFile type=\"ImageData\"><ImageData WholeExtent=\"0 3 0 3 0 3\"><Piece Extent=\"0 3 0 3 0 3\">"
                     "<PointData><DataArray type=\"UInt8\" Name=\"a\" format=\"binary\">AgAAAAEC</DataArray></PointData>"
                     "</Piece></ImageData></VTKFile>");
    expect_fail(dims, Kind::format, "DataArray holds 2 bytes, expected 64", dims, false);
}

TEST_CASE("bad volumes: wrong magic, versions, encodings, types, garbage headers", "[formats]") {
    TempDir dir("fmt-bad2");
    struct Case {
        const char* name;
        std::string text;
        const char* fragment;
    };
    const std::vector<Case> cases = {
        {"magic.nrrd", "NRRX0004\n" + kNrrdHead.substr(9) + "\n", "wrong magic"},
        {"version.nrrd", "NRRD0009\n" + kNrrdHead.substr(9) + "\n", "unsupported NRRD version 'NRRD0009'"},
        {"encoding.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: bzip2\n\n", "unsupported NRRD encoding 'bzip2'"},
        {"type.nrrd", "NRRD0004\ntype: quaternion\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n", "unknown NRRD type 'quaternion'"},
        {"garbage.nrrd", "NRRD0004\n\x01\x02garbage without colon\n\n", "bad NRRD header line"},
        {"sizes.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4\nencoding: raw\n\n", "'sizes' has 2 entries"},
        {"nodata.nhdr", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n", "neither a 'data file'"},
        {"pattern.nhdr", kNrrdHead + "data file: slice%s 1 4 1\n", "bad data file pattern"},
        // a width of 20 digits: refused, not overflowed (a UBSan finding of fuzz_nrrd)
        {"width.nhdr", kNrrdHead + "data file: slice%11111111111111111111d 1 4 1\n", "bad data file pattern"},
        {"width0.nhdr", kNrrdHead + "data file: slice%011111111111111111111 1 4 1\n", "bad data file pattern"},
        {"comp.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 3 4 4\nencoding: raw\nspace directions: none (1,0,0) (0,1,0)\n\n",
         "non-spatial axis of size 3"},
        {"type.mhd", "NDims = 3\nDimSize = 4 4 4\nElementType = MET_QUATERNION\nElementDataFile = LOCAL\n", "unsupported ElementType"},
        {"garbage.mhd", "NDims = 3\nthis is not a key value line\nElementDataFile = LOCAL\n", "bad MetaImage header line 2"},
        {"channels.mha", "NDims = 3\nDimSize = 4 4 4\nElementNumberOfChannels = 3\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
         "ElementNumberOfChannels 3"},
        {"magic.vtk", "# not vtk\n", "wrong magic"},
        {"grid.vtk", "# vtk DataFile Version 3.0\nx\nBINARY\nDATASET UNSTRUCTURED_GRID\n", "unsupported VTK dataset"},
        {"mode.vtk", "# vtk DataFile Version 3.0\nx\nHEX\nDATASET STRUCTURED_POINTS\n", "expected ASCII or BINARY"},
        {"count.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nPOINT_DATA 9\nSCALARS s float\n",
         "POINT_DATA 9 does not match"},
        {"bit.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nPOINT_DATA 8\nSCALARS s bit\n",
         "'bit'"},
        {"magic.slc", "22222\n4 4 4 8\n", "wrong magic"},
        {"bits.slc", "11111\n4 4 4 16\n1 1 1\n0 0 0 1\n", "bits per voxel 16"},
        {"notxml.vti", "\x89PNG garbage", "no <VTKFile>"},
        {"poly.vti", "<VTKFile type=\"PolyData\"></VTKFile>", "unsupported VTK XML type 'PolyData'"},
        {"lz4.vti", "<VTKFile type=\"ImageData\" compressor=\"vtkLZ4DataCompressor\"></VTKFile>", "unsupported compressor"},
        {"bad.json", "{\"vtkClass\": \"vtkImageData\", \"extent\": [0, 1,, 2]}", "bad JSON: The JSON document has an improper structure"},
        {"poly.json", "{\"vtkClass\": \"vtkPolyData\"}", "unsupported vtkClass"},
        {"fmt.dat", "ObjectFileName: x.raw\nResolution: 4 4 4\nFormat: BOGUS\n", "unknown Format 'BOGUS'"},
        {"nores.dat", "ObjectFileName: x.raw\nFormat: UCHAR\n", "missing Resolution"},
        {"unknown.xyz123", "hello world, not a volume\n", "unrecognized volume format"},
    };
    for (const auto& c : cases) {
        const std::string p = (dir / c.name).string();
        write_file(p, c.text);
        expect_fail(p, Kind::format, c.fragment);
    }
    // base64 garbage in a VTI payload
    const std::string b64 = (dir / "b64.vti").string();
    write_file(b64, "<VTKFile type=\"ImageData\"><ImageData WholeExtent=\"0 0 0 0 0 0\"><Piece Extent=\"0 0 0 0 0 0\">"
                    "<PointData><DataArray type=\"UInt8\" Name=\"a\" format=\"binary\">AQ*AAAA=</DataArray></PointData>"
                    "</Piece></ImageData></VTKFile>");
    expect_fail(b64, Kind::format, "bad base64 character '*'", b64, false);
    // corrupt zlib block in a VTI payload: 1 block of 8 bytes, compressed size 4, bytes "junk"
    const std::string zl = (dir / "zlib.vti").string();
    {
        std::vector<std::byte> bin;
        for (std::uint32_t v : {1u, 8u, 8u, 4u}) put_value(bin, v, false);
        for (char c : std::string("junk")) bin.push_back(std::byte(c));
        write_file(zl, "<VTKFile type=\"ImageData\" compressor=\"vtkZLibDataCompressor\"><ImageData WholeExtent=\"0 1 0 1 0 1\">"
                       "<Piece Extent=\"0 1 0 1 0 1\"><PointData><DataArray type=\"UInt8\" Name=\"a\" format=\"appended\" offset=\"0\"/>"
                       "</PointData></Piece></ImageData><AppendedData encoding=\"raw\">_",
                   bin);
    }
    expect_fail(zl, Kind::format, "corrupt compressed data", zl, false);
    // corrupt RLE: a run that overflows the slice
    const std::string rle = (dir / "rle.slc").string();
    {
        static const char text[] = "11111\n2 2 1 8\n1 1 1\n0 0 0 1\n0 0 X3 X\x7f\x05\x00";
        write_file(rle, std::string(text, sizeof text - 1));
    }
    expect_fail(rle, Kind::format, "corrupt RLE in slice 0", rle, false);
}

TEST_CASE("bad volumes: nifti byte order and header checks", "[formats]") {
    TempDir dir("fmt-bad3");
    auto header = [](std::int32_t sizeof_hdr, bool big, const char* magic, short datatype) {
        std::vector<std::byte> h;
        put_value<std::int32_t>(h, sizeof_hdr, big);
        h.resize(40);
        for (short d : {3, 2, 2, 2, 1, 1, 1, 1}) put_value<std::int16_t>(h, d, big);
        h.resize(70);
        put_value<std::int16_t>(h, datatype, big);
        h.resize(108);
        put_value<float>(h, 352, big);
        h.resize(344);
        for (int i = 0; i < 4; ++i) h.push_back(std::byte(magic[i]));
        h.resize(352 + 8);
        return h;
    };
    // big-endian header: sizeof_hdr is 348 only when byte-swapped -> read as big endian
    write_file((dir / "be.nii").string(), "", header(348, true, "n+1\0", 2));
    CHECK(read_volume((dir / "be.nii").string()).grid.dims == std::array<std::int64_t, 3>{2, 2, 2});
    // neither byte order gives 348
    write_file((dir / "size.nii").string(), "", header(1234, false, "n+1\0", 2));
    expect_fail((dir / "size.nii").string(), Kind::format, "sizeof_hdr is 1234, expected 348 in either byte order");
    write_file((dir / "v2.nii").string(), "", header(540, false, "n+2\0", 2));
    expect_fail((dir / "v2.nii").string(), Kind::format, "NIfTI-2");
    write_file((dir / "magic.nii").string(), "", header(348, false, "abc\0", 2));
    expect_fail((dir / "magic.nii").string(), Kind::format, "bad NIfTI magic");
    write_file((dir / "rgb.nii").string(), "", header(348, false, "n+1\0", 128));
    expect_fail((dir / "rgb.nii").string(), Kind::format, "unsupported NIfTI datatype 128");
    write_file((dir / "short.nii").string(), "", std::vector<std::byte>(100));
    expect_fail((dir / "short.nii").string(), Kind::format, "truncated");
    write_file((dir / "notgz.nii.gz").string(), "this is not gzip at all");
    expect_fail((dir / "notgz.nii.gz").string(), Kind::format, "corrupt compressed data");
}

TEST_CASE("bad volumes: missing files and directories", "[formats]") {
    TempDir dir("fmt-bad4");
    const std::string missing = (dir / "nope.nrrd").string();
    expect_fail(missing, Kind::io, "cannot open");
    expect_fail((dir / "nope_4x4x4_uint8.raw").string(), Kind::io, "cannot open");
    // a directory where a volume file was expected
    std::filesystem::create_directories(dir / "adir.raw");
    expect_fail((dir / "adir.raw").string(), Kind::io, "is a directory");
    std::filesystem::create_directories(dir / "plain_dir");
    expect_fail((dir / "plain_dir").string(), Kind::io, "is a directory");
    // header pointing at a missing data file / at a directory: the message names the header and
    // the data file (a copied header without its data: the newcomer trial's quarter.nhdr)
    write_file((dir / "miss.nhdr").string(), kNrrdHead + "data file: gone.raw\n");
    expect_fail((dir / "miss.nhdr").string(), Kind::io, "data file " + (dir / "gone.raw").string() + ": cannot open", "", false);
    std::filesystem::create_directories(dir / "sub");
    write_file((dir / "isdir.nhdr").string(), kNrrdHead + "data file: sub\n");
    expect_fail((dir / "isdir.nhdr").string(), Kind::io, "data file " + (dir / "sub").string() + ": is a directory", "", false);
    write_file((dir / "miss.mhd").string(), "NDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = gone.raw\n");
    expect_fail((dir / "miss.mhd").string(), Kind::io, "data file " + (dir / "gone.raw").string() + ": cannot open", "", false);
    write_file((dir / "miss.dat").string(), "ObjectFileName: gone.raw\nResolution: 4 4 4\nFormat: UCHAR\n");
    expect_fail((dir / "miss.dat").string(), Kind::io, "data file " + (dir / "gone.raw").string() + ": cannot open", "", false);
    // a data file too short: a format error, naming both
    write_file((dir / "short.raw").string(), "", std::vector<std::byte>(10));
    write_file((dir / "short.nhdr").string(), kNrrdHead + "data file: short.raw\n");
    expect_fail((dir / "short.nhdr").string(), Kind::format, "data file " + (dir / "short.raw").string() + ": expected 64 bytes", "",
                false);  // (probing reads headers only)
    std::filesystem::create_directories(dir / "js.vti");
    write_file((dir / "js.vti" / "index.json").string(),
               "{\"vtkClass\": \"vtkImageData\", \"extent\": [0,3,0,3,0,3], \"pointData\": {\"arrays\": [{\"data\": "
               "{\"dataType\": \"Uint8Array\", \"numberOfComponents\": 1, \"size\": 64, \"ref\": {\"basepath\": \"data\", "
               "\"id\": \"zz\", \"encode\": \"LittleEndian\"}}}]}}");
    expect_fail((dir / "js.vti").string(), Kind::io, "cannot open the array file", (dir / "js.vti" / "index.json").string());
    // raw without any layout information
    write_file((dir / "nolayout.raw").string(), "", std::vector<std::byte>(64));
    expect_fail((dir / "nolayout.raw").string(), Kind::format, "raw volume without layout");
}

TEST_CASE("bad volumes: ascii samples outside their type's range are refused and the extremes kept", "[formats]") {
    // converting such a value (or NaN) to the sample type is undefined behaviour; it used to wrap
    // silently (300 -> 44 in uint8)
    const std::vector<std::tuple<const char*, const char*, const char*>> bad = {
        {"uint8", "300 0 0 0 0 0 0 0", "'300' at value 0"},
        {"uint8", "0 -1 0 0 0 0 0 0", "'-1' at value 1"},
        {"uint8", "0 0 nan 0 0 0 0 0", "'nan' at value 2"},
        {"short", "0 0 0 -32769 0 0 0 0", "'-32769' at value 3"},
        {"unsigned short", "0 0 0 0 65536 0 0 0", "'65536' at value 4"},
        {"int", "0 0 0 0 0 2147483648 0 0", "'2147483648' at value 5"},
        {"float", "0 0 0 0 0 0 1e300 0", "'1e300' at value 6"},
        {"unsigned long long", "0 0 0 0 0 0 0 18446744073709551616", "'18446744073709551616' at value 7"},
        {"long long", "0 0 0 0 0 0 0 -1e19", "'-1e19' at value 7"},
        {"long long", "0 0 0 0 0 0 0 -9223372036854775809", "'-9223372036854775809' at value 7"},
    };
    for (const auto& [type, values, what] : bad) {
        TempDir d("ascii_range");
        const auto p = d.path / "v.nrrd";
        write_file(p, std::string("NRRD0004\ntype: ") + type + "\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n\n" + values + "\n", {});
        INFO(type << ": " << values);
        CHECK_THROWS_WITH(read_volume(p.string()), Catch::Contains(what) && Catch::Contains("is outside the range of"));
    }
    TempDir d("ascii_range_ok");
    const auto p = d.path / "ok.nrrd";
    const auto p64 = d.path / "ok64.nrrd";  // int64's extremes: -2^63 is exact as a double and is kept
    write_file(p64, "NRRD0004\ntype: long long\ndimension: 3\nsizes: 2 1 1\nencoding: ascii\n\n-9223372036854775808 9223372036854775807\n", {});
    const Volume v64 = read_volume(p64.string());
    REQUIRE(v64.type == SampleType::f32);  // (64-bit integers are read as float32 samples)
    CHECK(reinterpret_cast<const float*>(v64.bytes.data())[0] == static_cast<float>(std::numeric_limits<std::int64_t>::min()));
    CHECK(reinterpret_cast<const float*>(v64.bytes.data())[1] == static_cast<float>(std::numeric_limits<std::int64_t>::max()));
    write_file(p, "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n\n-32768 32767 -1.9 1.9 0 0 0 0\n", {});
    const Volume v = read_volume(p.string());
    REQUIRE(v.type == SampleType::i16);
    const auto* s = reinterpret_cast<const std::int16_t*>(v.bytes.data());
    CHECK(s[0] == -32768);
    CHECK(s[1] == 32767);
    CHECK(s[2] == -1);  // truncated toward zero, as before
    CHECK(s[3] == 1);
}

TEST_CASE("bad volumes: a compressed data file's decoding errors name the header that names it", "[formats]") {
    TempDir d("header_named");
    write_file((d.path / "small.bin").string(), "this is no zlib stream at all", {});
    write_file((d.path / "c.mhd").string(),
               "NDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nCompressedData = True\nElementDataFile = small.bin\n", {});
    write_file((d.path / "g.nhdr").string(), "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\ndata file: small.bin\n\n", {});
    for (const char* header : {"c.mhd", "g.nhdr"}) {
        INFO(header);
        CHECK_THROWS_WITH(read_volume((d.path / header).string()),
                          Catch::Contains(std::string(header) + ": data file ") && Catch::Contains("small.bin: "));
    }
}
