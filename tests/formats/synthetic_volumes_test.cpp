// Round trips: each format is written by the test from an analytic field (format_test_util.hpp)
// in every supported stored type and byte order, then read back and compared sample by sample.
// GCC 12 reports false -Wrestrict/-Warray-bounds/-Wstringop-overread positives inside libstdc++ string and vector
// inserts at -O2 (GCC bug 105329); they do not concern this file's code.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wrestrict"
#pragma GCC diagnostic ignored "-Warray-bounds"
#pragma GCC diagnostic ignored "-Wstringop-overread"
#endif
#include <catch2/catch.hpp>

#include <cmath>

#include "formats/base64.hpp"
#include "formats/volume_reader.hpp"
#include "tests/formats/format_test_util.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

constexpr std::array<std::int64_t, 3> kDims{7, 5, 3};
const StoredType kAllTypes[] = {StoredType::u8,  StoredType::i8,  StoredType::u16, StoredType::i16, StoredType::u32,
                                StoredType::i32, StoredType::u64, StoredType::i64, StoredType::f32, StoredType::f64};

Volume roundtrip(const std::string& path, StoredType t, const RawOptions& raw = {}) {
    INFO(path << " as " << to_string(t));
    REQUIRE(looks_like_volume(path));
    const VolumeInfo info = probe_volume(path, raw);
    const Volume v = read_volume(path, raw);
    CHECK(info.grid == v.grid);
    CHECK(info.type == v.type);
    CHECK(v.type == volume_type_for(t));
    CHECK(v.grid.dims == kDims);
    CHECK(mismatches(v, t) == 0);
    return v;
}

std::string nrrd_type(StoredType t) {
    switch (t) {
        case StoredType::u8: return "uchar";
        case StoredType::i8: return "signed char";
        case StoredType::u16: return "unsigned short";
        case StoredType::i16: return "short";
        case StoredType::u32: return "uint";
        case StoredType::i32: return "int";
        case StoredType::u64: return "unsigned long long int";
        case StoredType::i64: return "int64";
        case StoredType::f32: return "float";
        case StoredType::f64: return "double";
    }
    return "?";
}

}  // namespace

TEST_CASE("raw: name convention, options and .dat sidecars", "[formats]") {
    TempDir dir("fmt-raw");
    for (StoredType t : kAllTypes) {
        const std::string p = (dir / ("vol_7x5x3_" + std::string(to_string(t)) + ".raw")).string();
        write_file(p, "", field_bytes(t, kDims, false));
        roundtrip(p, t);
    }
    // options: dims/type/endian/spacing for a name without the convention
    const std::string p = (dir / "plain.raw").string();
    write_file(p, "", field_bytes(StoredType::u16, kDims, true));
    RawOptions o;
    o.dims = kDims;
    o.type = SampleType::u16;
    o.big_endian = true;
    o.spacing = std::array<double, 3>{0.5, 2, 3};
    const Volume v = roundtrip(p, StoredType::u16, o);
    CHECK(v.grid.spacing == std::array<double, 3>{0.5, 2, 3});
    // sidecar .dat with another stem (as silicium_98_34_34_uint8.dat) gives type and spacing
    const std::string q = (dir / "data_7x5x3.raw").string();
    write_file(q, "", field_bytes(StoredType::i16, kDims, false));
    write_file((dir / "other_name.dat").string(),
               "ObjectFileName: data_7x5x3.raw\nTaggedFileName: ---\nResolution:  7 5 3\nSliceThickness: 1.5 2 2.5\n"
               "Format:         SHORT\n\n\n");
    const Volume w = roundtrip(q, StoredType::i16);
    CHECK(w.grid.spacing == std::array<double, 3>{1.5, 2, 2.5});
    CHECK(read_volume((dir / "other_name.dat").string()).bytes == w.bytes);
}

TEST_CASE("nrrd: attached/detached, raw/gzip/ascii, both endians, every type", "[formats]") {
    TempDir dir("fmt-nrrd");
    int n = 0;
    for (StoredType t : kAllTypes)
        for (bool big : {false, true})
            for (const char* enc : {"raw", "gzip", "ascii"}) {
                const std::string head = "NRRD0004\n# test\ntype: " + nrrd_type(t) + "\ndimension: 3\nsizes: 7 5 3\n" +
                                         "endian: " + (big ? "big" : "little") + "\nencoding: " + enc +
                                         "\nspacings: 0.5 1 2\n";
                const auto payload = field_bytes(t, kDims, big);
                std::vector<std::byte> data = std::string(enc) == "raw"    ? payload
                                              : std::string(enc) == "gzip" ? deflate_bytes(payload, true)
                                                                           : to_bytes(field_text(t, kDims));
                const std::string a = (dir / ("a" + std::to_string(n) + ".nrrd")).string();
                write_file(a, head + "\n", data);
                CHECK(roundtrip(a, t).grid.spacing == std::array<double, 3>{0.5, 1, 2});
                const std::string d = (dir / ("d" + std::to_string(n) + ".nhdr")).string();
                write_file((dir / ("d" + std::to_string(n) + ".dat")).string(), "", data);
                write_file(d, head + "data file: d" + std::to_string(n) + ".dat\n");
                const VolumeInfo info = probe_volume(d);
                CHECK(info.encoding == std::string(enc));
                REQUIRE(info.data_files.size() == 1);
                roundtrip(d, t);
                ++n;
            }
}

TEST_CASE("nrrd: LIST, pattern, byte skip, line skip, space directions, 4-D", "[formats]") {
    TempDir dir("fmt-nrrd2");
    const StoredType t = StoredType::i16;
    const auto payload = field_bytes(t, kDims, false);
    const std::size_t slice = 7 * 5 * 2;
    for (int k = 0; k < 3; ++k) {
        std::vector<std::byte> s(payload.begin() + k * slice, payload.begin() + (k + 1) * slice);
        write_file((dir / ("slice" + std::to_string(10 + k) + ".raw")).string(), "", s);
        // with a 5-byte prefix for byte skip, and gzipped for the gzip+LIST case
        std::vector<std::byte> pre(5, std::byte{0x55});
        pre.insert(pre.end(), s.begin(), s.end());
        write_file((dir / ("skip" + std::to_string(k) + ".raw")).string(), "", pre);
        write_file((dir / ("z" + std::to_string(k) + ".gz")).string(), "", deflate_bytes(s, true));
    }
    const std::string common = "NRRD0005\ntype: int16\ndimension: 3\nsizes: 7 5 3\nendian: little\n";
    write_file((dir / "list.nhdr").string(), common + "encoding: raw\ndata file: LIST\nslice10.raw\nslice11.raw\nslice12.raw\n");
    CHECK(probe_volume((dir / "list.nhdr").string()).data_files.size() == 3);
    roundtrip((dir / "list.nhdr").string(), t);
    write_file((dir / "pat.nhdr").string(), common + "encoding: raw\ndata file: slice%d.raw 10 12 1 2\n");
    roundtrip((dir / "pat.nhdr").string(), t);
    write_file((dir / "patdown.nhdr").string(), common + "encoding: raw\ndata file: skip%d.raw 0 2 1\nbyte skip: 5\n");
    roundtrip((dir / "patdown.nhdr").string(), t);
    write_file((dir / "skipend.nhdr").string(), common + "encoding: raw\ndata file: skip%d.raw 0 2 1\nbyte skip: -1\n");
    roundtrip((dir / "skipend.nhdr").string(), t);
    write_file((dir / "gzlist.nhdr").string(), common + "encoding: gzip\ndata file: LIST\nz0.gz\nz1.gz\nz2.gz\n");
    roundtrip((dir / "gzlist.nhdr").string(), t);
    // line skip: two text lines before the data in the data file
    write_file((dir / "lines.raw").string(), "first line\nsecond\n", payload);
    write_file((dir / "lines.nhdr").string(), common + "encoding: raw\nline skip: 2\ndata file: lines.raw\n");
    roundtrip((dir / "lines.nhdr").string(), t);
    // space directions (spacing = vector length) and origin; extra size-1 axis in 4-D
    write_file((dir / "dirs.nrrd").string(),
               "NRRD0004\ntype: short\ndimension: 4\nsizes: 1 7 5 3\nendian: little\nencoding: raw\nspace: RAS\n"
               "space directions: none (0,0,3) (4,0,0) (0,0.5,0)\nspace origin: (1.5,-2,3)\nkinds: list space space space\n\n",
               payload);
    const Volume v = roundtrip((dir / "dirs.nrrd").string(), t);
    CHECK(v.grid.spacing == std::array<double, 3>{3, 4, 0.5});
    CHECK(v.grid.origin == std::array<double, 3>{1.5, -2, 3});
}

TEST_CASE("metaimage: .mhd and .mha LOCAL, byte order, HeaderSize, compression, every type", "[formats]") {
    TempDir dir("fmt-mhd");
    const std::pair<StoredType, const char*> types[] = {
        {StoredType::u8, "MET_UCHAR"}, {StoredType::i8, "MET_CHAR"},   {StoredType::u16, "MET_USHORT"},
        {StoredType::i16, "MET_SHORT"}, {StoredType::u32, "MET_UINT"}, {StoredType::i32, "MET_INT"},
        {StoredType::u64, "MET_ULONG_LONG"}, {StoredType::i64, "MET_LONG_LONG"}, {StoredType::f32, "MET_FLOAT"},
        {StoredType::f64, "MET_DOUBLE"}};
    int n = 0;
    for (const auto& [t, name] : types)
        for (bool big : {false, true}) {
            const auto payload = field_bytes(t, kDims, big);
            const std::string head = std::string("ObjectType = Image\nNDims = 3\nDimSize = 7 5 3\nElementSpacing = 0.5 1 2\n") +
                                     "Offset = -1 2 3.5\nElementByteOrderMSB = " + (big ? "True" : "False") +
                                     "\nElementType = " + name + "\n";
            const std::string m = (dir / ("m" + std::to_string(n) + ".mha")).string();
            write_file(m, head + "ElementDataFile = LOCAL\n", payload);
            const Volume v = roundtrip(m, t);
            CHECK(v.grid.origin == std::array<double, 3>{-1, 2, 3.5});
            CHECK(v.grid.spacing == std::array<double, 3>{0.5, 1, 2});
            // detached with a 16-byte HeaderSize
            std::vector<std::byte> pre(16, std::byte{0x77});
            pre.insert(pre.end(), payload.begin(), payload.end());
            write_file((dir / ("m" + std::to_string(n) + ".bin")).string(), "", pre);
            write_file((dir / ("h" + std::to_string(n) + ".mhd")).string(),
                       head + "HeaderSize = 16\nElementDataFile = m" + std::to_string(n) + ".bin\n");
            roundtrip((dir / ("h" + std::to_string(n) + ".mhd")).string(), t);
            // compressed .mha (zlib) with BinaryDataByteOrderMSB spelling
            std::string h2 = head;
            h2.replace(h2.find("ElementByteOrderMSB"), 19, "BinaryDataByteOrderMSB");
            const auto z = deflate_bytes(payload, false);
            write_file((dir / ("c" + std::to_string(n) + ".mha")).string(),
                       h2 + "CompressedData = True\nCompressedDataSize = " + std::to_string(z.size()) +
                           "\nElementDataFile = LOCAL\n",
                       z);
            roundtrip((dir / ("c" + std::to_string(n) + ".mha")).string(), t);
            ++n;
        }
}

TEST_CASE("vtk legacy: STRUCTURED_POINTS binary (big endian) and ascii", "[formats]") {
    TempDir dir("fmt-vtk");
    const std::pair<StoredType, const char*> types[] = {
        {StoredType::u8, "unsigned_char"}, {StoredType::i8, "char"},   {StoredType::u16, "unsigned_short"},
        {StoredType::i16, "short"},        {StoredType::u32, "unsigned_int"}, {StoredType::i32, "int"},
        {StoredType::i64, "vtktypeint64"}, {StoredType::f32, "float"}, {StoredType::f64, "double"}};
    int n = 0;
    for (const auto& [t, name] : types)
        for (bool binary : {true, false}) {
            const std::string head = std::string("# vtk DataFile Version 3.0\nsynthetic field\n") + (binary ? "BINARY" : "ASCII") +
                                     "\nDATASET STRUCTURED_POINTS\nDIMENSIONS 7 5 3\nSPACING 0.5 1 2\nORIGIN 1 2 3\n"
                                     "POINT_DATA 105\nSCALARS values " + name + (n % 2 ? " 1" : "") + "\n" +
                                     (n % 3 ? "LOOKUP_TABLE default\n" : "");
            const std::string p = (dir / ("v" + std::to_string(n++) + ".vtk")).string();
            if (binary)
                write_file(p, head, field_bytes(t, kDims, true));
            else
                write_file(p, head + field_text(t, kDims));
            const Volume v = roundtrip(p, t);
            CHECK(v.grid.spacing == std::array<double, 3>{0.5, 1, 2});
            CHECK(v.grid.origin == std::array<double, 3>{1, 2, 3});
        }
    // ASPECT_RATIO (VTK 1.0 spelling, as ironProt.vtk) and a FIELD array
    write_file((dir / "f.vtk").string(),
               "# vtk DataFile Version 2.0\n\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 7 5 3\nASPECT_RATIO 2 2 2\n"
               "POINT_DATA 105\nFIELD FieldData 1\nrho 1 105 float\n" + field_text(StoredType::f32, kDims));
    CHECK(roundtrip((dir / "f.vtk").string(), StoredType::f32).grid.spacing == std::array<double, 3>{2, 2, 2});
}

namespace {

template <class U>
void put_uint(std::vector<std::byte>& v, std::uint64_t x, bool big) {
    put_value(v, static_cast<U>(x), big);
}

// VTK XML binary data with header: uncompressed [nbytes][data] or zlib [n, bs, last, cs...][blocks]
std::vector<std::byte> vtk_xml_binary(const std::vector<std::byte>& data, bool compress, bool h64, bool big,
                                      std::size_t block = 64) {
    std::vector<std::byte> out;
    auto put = [&](std::uint64_t x) { h64 ? put_uint<std::uint64_t>(out, x, big) : put_uint<std::uint32_t>(out, x, big); };
    if (!compress) {
        put(data.size());
        out.insert(out.end(), data.begin(), data.end());
        return out;
    }
    std::vector<std::vector<std::byte>> blocks;
    for (std::size_t o = 0; o < data.size(); o += block)
        blocks.push_back(deflate_bytes(data.data() + o, std::min(block, data.size() - o), false));
    put(blocks.size());
    put(block);
    put(data.size() % block);
    for (const auto& b : blocks) put(b.size());
    for (const auto& b : blocks) out.insert(out.end(), b.begin(), b.end());
    return out;
}

std::string vti_xml_type(StoredType t) {
    switch (t) {
        case StoredType::u8: return "UInt8";
        case StoredType::i8: return "Int8";
        case StoredType::u16: return "UInt16";
        case StoredType::i16: return "Int16";
        case StoredType::u32: return "UInt32";
        case StoredType::i32: return "Int32";
        case StoredType::u64: return "UInt64";
        case StoredType::i64: return "Int64";
        case StoredType::f32: return "Float32";
        case StoredType::f64: return "Float64";
    }
    return "?";
}

}  // namespace

TEST_CASE("vti: inline base64 / appended raw / appended base64 / ascii, zlib with UInt32 and UInt64 headers", "[formats]") {
    TempDir dir("fmt-vti");
    int n = 0;
    for (StoredType t : kAllTypes)
        for (int mode = 0; mode < 8; ++mode) {
            const bool compress = mode & 1, h64 = mode & 2, big = mode & 4;
            const auto data = field_bytes(t, kDims, big);
            const auto bin = vtk_xml_binary(data, compress, h64, big);
            std::string head = std::string("<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"") +
                               (big ? "BigEndian" : "LittleEndian") + "\" header_type=\"" + (h64 ? "UInt64" : "UInt32") + "\"" +
                               (compress ? " compressor=\"vtkZLibDataCompressor\"" : "") + ">\n" +
                               "  <ImageData WholeExtent=\"2 8 0 4 1 3\" Origin=\"0 0 0\" Spacing=\"0.5 1 2\">\n" +
                               "  <Piece Extent=\"2 8 0 4 1 3\">\n    <PointData Scalars=\"f\">\n";
            const std::string decoy = "      <DataArray type=\"Float32\" Name=\"decoy\" format=\"ascii\">" +
                                      std::string(105 * 2, ' ') + "</DataArray>\n";
            const std::string tail = "    </PointData>\n  </Piece>\n  </ImageData>\n";
            // inline base64 (header and blocks encoded separately when compressed, as VTK does)
            std::string b64;
            if (compress) {
                const std::size_t hb = (h64 ? 8 : 4) * (3 + (data.size() + 63) / 64);
                b64 = base64_encode(bin.data(), hb) + base64_encode(bin.data() + hb, bin.size() - hb);
            } else {
                b64 = base64_encode(bin.data(), bin.size());
            }
            const std::string p1 = (dir / ("i" + std::to_string(n) + ".vti")).string();
            write_file(p1, head + decoy + "      <DataArray type=\"" + vti_xml_type(t) + "\" Name=\"f\" format=\"binary\">\n        " +
                               b64 + "\n      </DataArray>\n" + tail + "</VTKFile>\n");
            const Volume v = roundtrip(p1, t);
            CHECK(v.grid.origin == std::array<double, 3>{1, 0, 2});
            CHECK(v.grid.spacing == std::array<double, 3>{0.5, 1, 2});
            // appended raw: a first array occupies offset 0, ours follows
            const auto other = vtk_xml_binary(std::vector<std::byte>(105 * 4), compress, h64, big);
            const std::string p2 = (dir / ("a" + std::to_string(n) + ".vti")).string();
            std::vector<std::byte> app = other;
            app.insert(app.end(), bin.begin(), bin.end());
            write_file(p2,
                       head + "      <DataArray type=\"Float32\" Name=\"g\" format=\"appended\" offset=\"0\"/>\n" +
                           "      <DataArray type=\"" + vti_xml_type(t) + "\" Name=\"f\" format=\"appended\" offset=\"" +
                           std::to_string(other.size()) + "\"/>\n" + tail + "  <AppendedData encoding=\"raw\">\n   _",
                       app);
            {
                std::ofstream f(p2, std::ios::app);
                f << "\n  </AppendedData>\n</VTKFile>\n";
            }
            roundtrip(p2, t);
            // appended base64 (uncompressed only: one encoding of header+data)
            if (!compress) {
                const std::string p3 = (dir / ("b" + std::to_string(n) + ".vti")).string();
                write_file(p3, head + "      <DataArray type=\"" + vti_xml_type(t) +
                                   "\" Name=\"f\" format=\"appended\" offset=\"0\"/>\n" + tail +
                                   "  <AppendedData encoding=\"base64\">\n   _" + base64_encode(bin.data(), bin.size()) +
                                   "\n  </AppendedData>\n</VTKFile>\n");
                roundtrip(p3, t);
            }
            ++n;
        }
    const std::string p4 = (dir / "ascii.vti").string();
    write_file(p4, "<VTKFile type=\"ImageData\" version=\"0.1\">\n<ImageData WholeExtent=\"0 6 0 4 0 2\" Origin=\"0 0 0\" "
                   "Spacing=\"1 1 1\">\n<Piece Extent=\"0 6 0 4 0 2\">\n<PointData>\n<DataArray type=\"Float64\" Name=\"x\" "
                   "format=\"ascii\">\n" + field_text(StoredType::f64, kDims) +
                   "</DataArray>\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n");
    roundtrip(p4, StoredType::f64);
}

TEST_CASE("vtk-js: index.json with a gzipped or raw array, directory or index path", "[formats]") {
    TempDir dir("fmt-vtkjs");
    const std::pair<StoredType, const char*> types[] = {{StoredType::u8, "Uint8Array"},   {StoredType::i16, "Int16Array"},
                                                        {StoredType::u16, "Uint16Array"}, {StoredType::i32, "Int32Array"},
                                                        {StoredType::f32, "Float32Array"}, {StoredType::f64, "Float64Array"}};
    int n = 0;
    for (const auto& [t, name] : types)
        for (bool gz : {true, false}) {
            const auto root = dir.path / ("img" + std::to_string(n++) + ".vti");
            std::filesystem::create_directories(root / "data");
            const auto data = field_bytes(t, kDims, false);
            if (gz)
                write_file((root / "data" / "abc123.gz").string(), "", deflate_bytes(data, true));
            else
                write_file((root / "data" / "abc123").string(), "", data);
            write_file((root / "index.json").string(),
                       std::string("{\"origin\": [1, 2, 3], \"spacing\": [0.5, 1, 2], \"extent\": [0, 6, 0, 4, 0, 2],\n") +
                           "\"vtkClass\": \"vtkImageData\", \"pointData\": {\"vtkClass\": \"vtkDataSetAttributes\", \"arrays\": [\n" +
                           "{\"data\": {\"numberOfComponents\": 1, \"name\": \"s\", \"vtkClass\": \"vtkDataArray\", \"dataType\": \"" +
                           name + "\", \"ref\": {\"registration\": \"setScalars\", \"encode\": \"LittleEndian\", \"basepath\": \"data\", "
                           "\"id\": \"abc123\"}, \"size\": 105}}]}, \"metadata\": {\"name\": \"x\\u00e9\"}}");
            const Volume a = roundtrip(root.string(), t);
            CHECK(a.grid.origin == std::array<double, 3>{1, 2, 3});
            CHECK(a.grid.spacing == std::array<double, 3>{0.5, 1, 2});
            CHECK(roundtrip((root / "index.json").string(), t).bytes == a.bytes);
            CHECK(probe_volume(root.string()).encoding == (gz ? "gzip" : "raw"));
        }
}

namespace {
std::vector<std::byte> slc_rle(const std::vector<std::byte>& in) {
    std::vector<std::byte> out;
    std::size_t i = 0;
    while (i < in.size()) {
        std::size_t run = 1;
        while (i + run < in.size() && run < 127 && in[i + run] == in[i]) ++run;
        if (run >= 2) {
            out.push_back(std::byte(run));
            out.push_back(in[i]);
            i += run;
            continue;
        }
        std::size_t lit = 1;
        while (i + lit < in.size() && lit < 127 && !(i + lit + 1 < in.size() && in[i + lit] == in[i + lit + 1])) ++lit;
        out.push_back(std::byte(0x80 | lit));
        out.insert(out.end(), in.begin() + i, in.begin() + i + lit);
        i += lit;
    }
    out.push_back(std::byte{0});
    return out;
}
}  // namespace

TEST_CASE("slc: RLE and uncompressed slices, icon skipped", "[formats]") {
    TempDir dir("fmt-slc");
    const auto data = field_bytes(StoredType::u8, kDims, false);
    for (int compression : {1, 0}) {
        std::string head = "11111\n7 5 3 8\n1.000000 2.000000 0.500000\n2 0 0 " + std::to_string(compression) + "\n3 2 X";
        std::vector<std::byte> body(3 * 2 * 3, std::byte{'X'});  // icon bytes that look like markers
        for (int k = 0; k < 3; ++k) {
            std::vector<std::byte> s(data.begin() + k * 35, data.begin() + (k + 1) * 35);
            const auto enc = compression ? slc_rle(s) : s;
            const auto lead = to_bytes(std::to_string(enc.size()) + " X");
            body.insert(body.end(), lead.begin(), lead.end());
            body.insert(body.end(), enc.begin(), enc.end());
        }
        const std::string p = (dir / ("v" + std::to_string(compression) + ".slc")).string();
        write_file(p, head, body);
        const Volume v = roundtrip(p, StoredType::u8);
        CHECK(v.grid.spacing == std::array<double, 3>{1, 2, 0.5});
        CHECK(probe_volume(p).encoding == (compression ? "rle" : "raw"));
    }
}

namespace {
// A NIfTI-1 header for the synthetic field; `big` writes every field big endian.
std::vector<std::byte> nifti_header(short datatype, short bitpix, bool big, float slope, float inter, const char* magic,
                                    float vox_offset) {
    std::vector<std::byte> h;
    put_value<std::int32_t>(h, 348, big);
    h.resize(40);
    const short dim[8] = {3, 7, 5, 3, 1, 1, 1, 1};
    for (short d : dim) put_value<std::int16_t>(h, d, big);
    h.resize(70);
    put_value<std::int16_t>(h, datatype, big);
    put_value<std::int16_t>(h, bitpix, big);
    h.resize(76);
    const float pix[8] = {1, 0.5f, -1.5f, 2, 1, 1, 1, 1};
    for (float p : pix) put_value<float>(h, p, big);
    put_value<float>(h, vox_offset, big);
    put_value<float>(h, slope, big);
    put_value<float>(h, inter, big);
    h.resize(252);
    put_value<std::int16_t>(h, 1, big);  // qform_code
    put_value<std::int16_t>(h, 0, big);  // sform_code
    h.resize(268);
    for (float o : {10.0f, -20.0f, 30.0f}) put_value<float>(h, o, big);
    h.resize(344);
    for (int i = 0; i < 4; ++i) h.push_back(std::byte(magic[i]));
    return h;
}
}  // namespace

TEST_CASE("nifti: .nii both endians, .nii.gz, .hdr/.img, scl_slope scaling", "[formats]") {
    TempDir dir("fmt-nii");
    const std::tuple<StoredType, short, short> types[] = {
        {StoredType::u8, 2, 8},     {StoredType::i16, 4, 16},   {StoredType::i32, 8, 32},   {StoredType::f32, 16, 32},
        {StoredType::f64, 64, 64},  {StoredType::i8, 256, 8},   {StoredType::u16, 512, 16}, {StoredType::u32, 768, 32},
        {StoredType::i64, 1024, 64}, {StoredType::u64, 1280, 64}};
    int n = 0;
    for (const auto& [t, dt, bp] : types)
        for (bool big : {false, true}) {
            auto file = nifti_header(dt, bp, big, 0, 0, "n+1\0", 352);
            file.resize(352);
            const auto data = field_bytes(t, kDims, big);
            file.insert(file.end(), data.begin(), data.end());
            const std::string p = (dir / ("v" + std::to_string(n) + ".nii")).string();
            write_file(p, "", file);
            const Volume v = roundtrip(p, t);
            CHECK(v.grid.spacing == std::array<double, 3>{0.5, 1.5, 2});
            CHECK(v.grid.origin == std::array<double, 3>{10, -20, 30});
            write_file(p + ".gz", "", deflate_bytes(file, true));
            CHECK(roundtrip(p + ".gz", t).bytes == v.bytes);
            CHECK(probe_volume(p + ".gz").encoding == "gzip");
            // header/image pair
            write_file((dir / ("p" + std::to_string(n) + ".hdr")).string(), "", nifti_header(dt, bp, big, 1, 0, "ni1\0", 0));
            write_file((dir / ("p" + std::to_string(n) + ".img")).string(), "", data);
            CHECK(roundtrip((dir / ("p" + std::to_string(n) + ".hdr")).string(), t).bytes == v.bytes);
            ++n;
        }
    // scaling: stored u8 b, value 0.5*b - 3 as float32
    auto file = nifti_header(2, 8, false, 0.5f, -3.0f, "n+1\0", 352);
    file.resize(352);
    const auto data = field_bytes(StoredType::u8, kDims, false);
    file.insert(file.end(), data.begin(), data.end());
    write_file((dir / "scaled.nii").string(), "", file);
    const Volume s = read_volume((dir / "scaled.nii").string());
    REQUIRE(s.type == SampleType::f32);
    CHECK(probe_volume((dir / "scaled.nii").string()).type == SampleType::f32);
    std::int64_t bad = 0;
    for (std::int64_t k = 0; k < 3; ++k)
        for (std::int64_t j = 0; j < 5; ++j)
            for (std::int64_t i = 0; i < 7; ++i)
                bad += s.view().at(i, j, k) != 0.5 * field_value(StoredType::u8, i, j, k) - 3.0;
    CHECK(bad == 0);
}
