// The must-fail corpus: per format, one generated file per defect class (sizes that
// overflow, a decompression bomb, a truncated or corrupt payload, control bytes in header fields,
// nonsense geometry), each run through the real `meshless` binary. Every case must exit 2 with a
// one-line message that names the file, carry no control byte (ESC, CR, ...) to the terminal,
// leave no output file (nor a temporary) behind, and stay within a bounded resident set.
// No file is copied from shared data: every byte is written here.
#include <sys/resource.h>
#include <sys/stat.h>
#include <zlib.h>
#include <zstd.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_harness.hpp"
#include "formats/crc32.hpp"

namespace fs = std::filesystem;
using namespace meshless::test;

namespace {

const std::string kEsc = "\x1b[31mRED\x1b[0m\x07";

std::string zeros(std::size_t n) { return std::string(n, '\0'); }

// A gzip member holding `plain`.
std::string gzip_of(const std::string& plain) {
    z_stream zs{};
    REQUIRE(deflateInit2(&zs, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) == Z_OK);
    std::string out(deflateBound(&zs, plain.size()) + 64, '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(plain.data()));
    zs.avail_in = static_cast<uInt>(plain.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = static_cast<uInt>(out.size());
    REQUIRE(deflate(&zs, Z_FINISH) == Z_STREAM_END);
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}

// A zlib stream holding `plain` (VTK XML's vtkZLibDataCompressor blocks).
std::string zlib_of(const std::string& plain) {
    uLongf n = compressBound(plain.size());
    std::string out(n, '\0');
    REQUIRE(compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(plain.data()), plain.size(), 9) == Z_OK);
    out.resize(n);
    return out;
}

std::string u32le(std::uint32_t v) {
    std::string s(4, '\0');
    std::memcpy(s.data(), &v, 4);
    return s;
}

// A DICOM slice file in explicit VR little endian (or `syntax`), written byte by byte: the meta group,
// then the attributes the series reader takes; `pixels` as Pixel Data (an encapsulated syntax gets
// an undefined-length item sequence holding one empty fragment).
std::string dcm_element(std::uint16_t g, std::uint16_t e, const char* vr, std::string v) {
    if (v.size() % 2) v += (std::string(vr) == "UI" || std::string(vr) == "OB") ? '\0' : ' ';
    std::string out(4, '\0');
    std::memcpy(out.data(), &g, 2);
    std::memcpy(out.data() + 2, &e, 2);
    out += vr;
    const std::string long_vrs = "OB OW OF SQ UT UN";
    if (long_vrs.find(vr) != std::string::npos) {
        out += std::string(2, '\0') + u32le(static_cast<std::uint32_t>(v.size()));
    } else {
        const auto n = static_cast<std::uint16_t>(v.size());
        out += std::string(reinterpret_cast<const char*>(&n), 2);
    }
    return out + v;
}
std::string us(std::uint16_t v) { return std::string(reinterpret_cast<const char*>(&v), 2); }
std::string dicom_slice(std::uint16_t rows, std::uint16_t cols, const std::string& pixels, const std::string& position = "0\\0\\0",
                        const std::string& description = "s", const std::string& series = "1.2.3.4",
                        const std::string& syntax = "1.2.840.10008.1.2.1", const std::string& photometric = "MONOCHROME2") {
    std::string meta = dcm_element(2, 1, "OB", std::string("\0\1", 2)) + dcm_element(2, 2, "UI", "1.2.840.10008.5.1.4.1.1.2") +
                       dcm_element(2, 3, "UI", "1.2.3.4.5") + dcm_element(2, 0x10, "UI", syntax);
    std::string out = std::string(128, '\0') + "DICM" + dcm_element(2, 0, "UL", u32le(static_cast<std::uint32_t>(meta.size()))) + meta;
    out += dcm_element(8, 0x16, "UI", "1.2.840.10008.5.1.4.1.1.2") + dcm_element(8, 0x18, "UI", "1.2.3.4.5") +
           dcm_element(8, 0x103e, "LO", description) + dcm_element(0x20, 0x0e, "UI", series) +
           dcm_element(0x20, 0x32, "DS", position) + dcm_element(0x20, 0x37, "DS", "1\\0\\0\\0\\1\\0") +
           dcm_element(0x28, 2, "US", us(1)) + dcm_element(0x28, 4, "CS", photometric) + dcm_element(0x28, 0x10, "US", us(rows)) +
           dcm_element(0x28, 0x11, "US", us(cols)) + dcm_element(0x28, 0x30, "DS", "1\\1") + dcm_element(0x28, 0x100, "US", us(16)) +
           dcm_element(0x28, 0x101, "US", us(16)) + dcm_element(0x28, 0x102, "US", us(15)) + dcm_element(0x28, 0x103, "US", us(0));
    if (syntax == "1.2.840.10008.1.2.1") return out + dcm_element(0x7fe0, 0x10, "OW", pixels);
    std::string px = std::string("\xe0\x7f\x10\x00OB\0\0\xff\xff\xff\xff", 12);
    px += std::string("\xfe\xff\x00\xe0", 4) + u32le(0);                        // the basic offset table, empty
    px += std::string("\xfe\xff\x00\xe0", 4) + u32le(static_cast<std::uint32_t>(pixels.size())) + pixels;  // one fragment
    px += std::string("\xfe\xff\xdd\xe0", 4) + u32le(0);                        // the sequence delimiter
    return out + px;
}

struct Case {
    std::string label;                                       // format / defect class
    std::string file;                                        // the file the command reads
    std::vector<std::pair<std::string, std::string>> files;  // name -> bytes (the first is `file`)
    bool volume = true;                                      // volume (info + isosurface) or point set (info + fit)
};

std::string nrrd(const std::string& fields, const std::string& payload) {
    return "NRRD0004\n" + fields + "\n" + payload;
}

std::string mha(const std::string& fields, const std::string& payload) {
    return "ObjectType = Image\n" + fields + "ElementDataFile = LOCAL\n" + payload;
}

std::string vtk_legacy(const std::string& dims, const std::string& spacing, const std::string& points,
                       const std::string& dataset, const std::string& payload) {
    return "# vtk DataFile Version 3.0\ntitle\nBINARY\nDATASET " + dataset + "\nDIMENSIONS " + dims + "\nSPACING " +
           spacing + "\nORIGIN 0 0 0\nPOINT_DATA " + points + "\nSCALARS s unsigned_char\nLOOKUP_TABLE default\n" + payload;
}

std::string vti(const std::string& extent, const std::string& spacing, const std::string& origin, const std::string& type,
                const std::string& array, const std::string& compressor = "") {
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + type + "\" version=\"0.1\" byte_order=\"LittleEndian\"" +
           (compressor.empty() ? "" : " compressor=\"" + compressor + "\"") + ">\n<ImageData WholeExtent=\"" + extent +
           "\" Origin=\"" + origin + "\" Spacing=\"" + spacing + "\">\n<Piece Extent=\"" + extent +
           "\">\n<PointData Scalars=\"s\">\n" + array + "</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
}

std::string vtkjs_index(const std::string& extent, const std::string& spacing, const std::string& type) {
    return "{\"vtkClass\":\"vtkImageData\",\"extent\":[" + extent + "],\"spacing\":[" + spacing +
           "],\"origin\":[0,0,0],\"pointData\":{\"arrays\":[{\"data\":{\"dataType\":\"" + type +
           "\",\"numberOfComponents\":1,\"ref\":{\"id\":\"s\",\"basepath\":\"data\",\"encode\":\"LittleEndian\","
           "\"registration\":\"setScalars\"}}}]}}";
}

std::string slc(const std::string& dims, const std::string& spacing, const std::string& compression,
                const std::string& body, const std::string& magic = "11111") {
    return magic + "\n" + dims + " 8\n" + spacing + "\n0 0 0 " + compression + "\n0 0 X\n" + body;
}

// NIfTI-1 single file (n+1): dims, datatype uint8, pixdim, sform origin.
std::string nifti(std::int16_t nx, std::int16_t ny, std::int16_t nz, float sx, float ox, const std::string& payload) {
    std::string h(352, '\0');
    auto put16 = [&](std::size_t off, std::int16_t v) { std::memcpy(h.data() + off, &v, 2); };
    auto put32 = [&](std::size_t off, std::int32_t v) { std::memcpy(h.data() + off, &v, 4); };
    auto putf = [&](std::size_t off, float v) { std::memcpy(h.data() + off, &v, 4); };
    put32(0, 348);
    put16(40, 3);
    put16(42, nx);
    put16(44, ny);
    put16(46, nz);
    put16(70, 2);   // DT_UINT8
    put16(72, 8);   // bitpix
    putf(80, sx);
    putf(84, 1);
    putf(88, 1);
    putf(108, 352);  // vox_offset
    putf(112, 1);    // scl_slope
    put16(254, 1);   // sform_code
    putf(280 + 12, ox);
    std::memcpy(h.data() + 344, "n+1\0", 4);
    return h + payload;
}

std::vector<Case> corpus() {
    const std::string big = "4294967296 4294967296 1";
    const std::string gz1 = gzip_of("x");
    std::vector<Case> c;
    auto add = [&](std::string label, std::string name, std::string bytes, bool volume = true) {
        c.push_back(Case{std::move(label), name, {{name, std::move(bytes)}}, volume});
    };
    // raw (layout from the name convention)
    add("raw overflowing dims", "ov_4294967296x4294967296x1_uint8.raw", zeros(100));
    add("raw truncated payload", "tr_64x64x64_uint8.raw", zeros(1000));
    // NRRD
    add("nrrd overflowing dims", "ov.nrrd", nrrd("type: uint8\ndimension: 3\nsizes: " + big + "\nencoding: raw\n", zeros(100)));
    add("nrrd overflowing dims (2^63)", "ov63.nrrd",
        nrrd("type: float\ndimension: 3\nsizes: 9223372036854775807 2 2\nencoding: raw\n", zeros(100)));
    add("nrrd gzip bomb", "bomb.nrrd", nrrd("type: uint8\ndimension: 3\nsizes: 2048 2048 1024\nencoding: gzip\n", gz1));
    add("nrrd truncated gzip", "trgz.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 16 16 16\nencoding: gzip\n", gzip_of(zeros(1000))));
    add("nrrd corrupt gzip", "corrupt.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 16 16 16\nencoding: gzip\n", "\x1f\x8b\x08\x00garbage-garbage-garbage"));
    // the gzip tail rule (formats/gzip.hpp): after the payload's bytes, a further member, whole or
    // only begun, is refused by info and every reader with the same words
    add("nrrd gzip payload and a second gzip member", "twomember.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\n", gzip_of(zeros(64)) + gzip_of("x")));
    add("nrrd gzip payload and stray gzip magic", "straymagic.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\n", gzip_of(zeros(64)) + "\x1f\x8b"));
    add("nrrd truncated raw", "trraw.nrrd", nrrd("type: uint8\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n", zeros(100)));
    add("nrrd truncated ascii", "trascii.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 1024 1024 1024\nencoding: ascii\n", "1 2 3 4\n"));
    add("nrrd control bytes", "esc.nrrd", nrrd("type: " + kEsc + "\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n", zeros(64)));
    add("nrrd infinite spacing", "infsp.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 4 4 4\nspacings: inf 1 1\nencoding: raw\n", zeros(64)));
    add("nrrd zero spacing", "zerosp.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 4 4 4\nspacings: 0 1 1\nencoding: raw\n", zeros(64)));
    add("nrrd NaN origin", "nanorg.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 4 4 4\nspace origin: (nan,0,0)\nencoding: raw\n", zeros(64)));
    // finite doubles whose sample positions overflow the float32 records (every point would be infinite)
    add("nrrd spacing overflowing float positions", "farsp.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 4 4 4\nspacings: 1e308 1e308 1e308\nencoding: raw\n", zeros(64)));
    add("nrrd origin beyond float32", "farorg.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 4 4 4\nspace origin: (1e39,0,0)\nencoding: raw\n", zeros(64)));
    add("nrrd data file range overflow", "range.nrrd",
        nrrd("type: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: f%d.raw -9223372036854775807 9223372036854775807 1\n", ""));
    // MetaImage
    add("mha overflowing dims", "ov.mha", mha("NDims = 3\nDimSize = " + big + "\nElementType = MET_UCHAR\n", zeros(100)));
    add("mha compressed bomb", "bomb.mha",
        mha("NDims = 3\nDimSize = 2048 2048 1024\nElementType = MET_UCHAR\nCompressedData = True\n", gz1));
    add("mha truncated", "tr.mha", mha("NDims = 3\nDimSize = 16 16 16\nElementType = MET_UCHAR\n", zeros(10)));
    add("mha control bytes", "esc.mha", mha("NDims = 3\nDimSize = 4 4 4\nElementType = " + kEsc + "\n", zeros(64)));
    add("mha NaN spacing", "nansp.mha",
        mha("NDims = 3\nDimSize = 4 4 4\nElementSpacing = nan 1 1\nElementType = MET_UCHAR\n", zeros(64)));
    add("mha NaN origin", "nanorg.mha",
        mha("NDims = 3\nDimSize = 4 4 4\nOffset = nan 0 0\nElementType = MET_UCHAR\n", zeros(64)));
    add("mha spacing overflowing float positions", "farsp.mha",
        mha("NDims = 3\nDimSize = 4 4 4\nElementSpacing = 1e308 1 1\nElementType = MET_UCHAR\n", zeros(64)));
    add("mha offset beyond float32", "farorg.mha",
        mha("NDims = 3\nDimSize = 4 4 4\nOffset = 0 -1e300 0\nElementType = MET_UCHAR\n", zeros(64)));
    // VTK legacy
    add("vtk spacing overflowing float positions", "farsp.vtk", vtk_legacy("4 4 4", "1e300 1 1", "64", "STRUCTURED_POINTS", zeros(64)));
    add("vtk overflowing dims", "ov.vtk", vtk_legacy(big, "1 1 1", "0", "STRUCTURED_POINTS", zeros(100)));
    add("vtk truncated", "tr.vtk", vtk_legacy("16 16 16", "1 1 1", "4096", "STRUCTURED_POINTS", zeros(100)));
    add("vtk control bytes", "esc.vtk", vtk_legacy("4 4 4", "1 1 1", "64", kEsc, zeros(64)));
    add("vtk NaN spacing", "nansp.vtk", vtk_legacy("4 4 4", "nan 1 1", "64", "STRUCTURED_POINTS", zeros(64)));
    // VTK XML ImageData
    const std::string ascii_array = "<DataArray type=\"UInt8\" Name=\"s\" format=\"ascii\">\n1 2 3\n</DataArray>\n";
    add("vti overflowing extent", "ov.vti", vti("0 4294967295 0 4294967295 0 0", "1 1 1", "0 0 0", "ImageData", ascii_array));
    add("vti signed extent overflow", "ov63.vti",
        vti("-9223372036854775808 9223372036854775807 0 0 0 0", "1 1 1", "0 0 0", "ImageData", ascii_array));
    {
        // one zlib block whose header claims 2048*2048*1024 bytes: base64 of [1, bsize, last, csize] + data
        const std::string block = zlib_of("x");
        const std::string bin = u32le(1) + u32le(0) + u32le(0) + u32le(static_cast<std::uint32_t>(block.size())) + block;
        // appended raw: the bytes follow '_' directly
        const std::string doc =
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\" "
            "compressor=\"vtkZLibDataCompressor\">\n<ImageData WholeExtent=\"0 2047 0 2047 0 1023\" Origin=\"0 0 0\" "
            "Spacing=\"1 1 1\">\n<Piece Extent=\"0 2047 0 2047 0 1023\">\n<PointData Scalars=\"s\">\n<DataArray "
            "type=\"UInt8\" Name=\"s\" format=\"appended\" offset=\"0\"/>\n</PointData>\n</Piece>\n</ImageData>\n"
            "<AppendedData encoding=\"raw\">\n_";
        // bsize 2^31 with 2 blocks: 2^32 bytes = 2048*2048*1024
        const std::string hdr = u32le(2) + u32le(0x80000000u) + u32le(0) + u32le(static_cast<std::uint32_t>(block.size())) +
                                u32le(static_cast<std::uint32_t>(block.size()));
        add("vti zlib bomb", "bomb.vti", doc + hdr + block + block + "\n</AppendedData>\n</VTKFile>\n");
        (void)bin;
    }
    add("vti truncated ascii", "tr.vti", vti("0 99 0 99 0 99", "1 1 1", "0 0 0", "ImageData", ascii_array));
    add("vti control bytes", "esc.vti", vti("0 3 0 3 0 3", "1 1 1", "0 0 0", kEsc, ascii_array));
    add("vti NaN spacing", "nansp.vti", vti("0 0 0 0 0 2", "nan 1 1", "0 0 0", "ImageData", ascii_array));
    add("vti spacing overflowing float positions", "farsp.vti", vti("0 0 0 0 0 2", "1 1 1e300", "0 0 0", "ImageData", ascii_array));
    add("vti NaN origin", "nanorg.vti", vti("0 0 0 0 0 2", "1 1 1", "nan 0 0", "ImageData", ascii_array));
    // vtk.js (index.json + data/s.gz)
    c.push_back(Case{"vtkjs gzip bomb", "bomb/index.json",
                     {{"bomb/index.json", vtkjs_index("0,2047,0,2047,0,1023", "1,1,1", "Uint8Array")}, {"bomb/data/s.gz", gz1}}});
    c.push_back(Case{"vtkjs overflowing extent", "ovjs/index.json",
                     {{"ovjs/index.json", vtkjs_index("0,4294967295,0,4294967295,0,0", "1,1,1", "Uint8Array")},
                      {"ovjs/data/s", zeros(100)}}});
    c.push_back(Case{"vtkjs huge extent", "hugejs/index.json",
                     {{"hugejs/index.json", vtkjs_index("0,1e300,0,0,0,0", "1,1,1", "Uint8Array")}, {"hugejs/data/s", zeros(100)}}});
    c.push_back(Case{"vtkjs spacing putting samples beyond float32", "farjs/index.json",
                     {{"farjs/index.json", vtkjs_index("0,3,0,3,0,3", "2e38,1,1", "Uint8Array")}, {"farjs/data/s", zeros(64)}}});
    c.push_back(Case{"vtkjs control bytes", "escjs/index.json",
                     {{"escjs/index.json", vtkjs_index("0,3,0,3,0,3", "1,1,1", "\\u001b[31mX")}, {"escjs/data/s", zeros(64)}}});
    c.push_back(Case{"vtkjs zero spacing", "zerojs/index.json",
                     {{"zerojs/index.json", vtkjs_index("0,3,0,3,0,3", "0,1,1", "Uint8Array")}, {"zerojs/data/s", zeros(64)}}});
    // SLC
    add("slc overflowing dims", "ov.slc", slc("4294967296 4294967296 1", "1 1 1", "1", "2 X\x81\x01"));
    add("slc rle bomb", "bomb.slc", slc("1048576 1048576 4", "1 1 1", "1", "2 X\x01\x00" "2 X\x01\x00" "2 X\x01\x00" "2 X\x01\x00"));
    add("slc short slices", "short.slc", slc("1048576 1 64", "1 1 1", "1", [] {
            std::string s;
            for (int z = 0; z < 64; ++z) s += "2 X\x81\x07";
            return s;
        }()));
    add("slc truncated", "tr.slc", slc("16 16 16", "1 1 1", "0", "256 X" + zeros(10)));
    add("slc control bytes", "esc.slc", slc("4 4 4", "1 1 1", "0", "", "11111" + kEsc));
    add("slc NaN spacing", "nansp.slc", slc("4 4 4", "nan 1 1", "0", "16 X" + zeros(16)));
    add("slc icon overflow", "icon.slc",
        "11111\n4 4 4 8\n1 1 1\n0 0 0 0\n4294967296 4294967296 X\n" + zeros(64));
    // NIfTI-1
    add("nifti gzip bomb", "bomb.nii.gz", gzip_of(nifti(32767, 32767, 32767, 1, 0, "")));
    add("nifti truncated", "tr.nii", nifti(64, 64, 64, 1, 0, zeros(100)));
    add("nifti NaN origin", "nanorg.nii", nifti(4, 4, 4, 1, std::nanf(""), zeros(64)));
    // DICOM (each in its own folder: a slice file is read as its folder's series)
    c.push_back(Case{"dicom Rows x Columns beyond the file", "dcmclaim/s.dcm", {{"dcmclaim/s.dcm", dicom_slice(65535, 65535, zeros(8))}}});
    c.push_back(Case{"dicom compressed bomb", "dcmbomb/s.dcm",
                     {{"dcmbomb/s.dcm", dicom_slice(65535, 65535, zeros(64), "0\\0\\0", "s", "1.2.3.4", "1.2.840.10008.1.2.5")}}});
    c.push_back(Case{"dicom truncated pixel data", "dcmtrunc/s.dcm",
                     {{"dcmtrunc/s.dcm", dicom_slice(64, 64, zeros(8192)).substr(0, 600 + 4096)}}});
    c.push_back(Case{"dicom control bytes in a Photometric Interpretation", "dcmesc/s.dcm",
                     {{"dcmesc/s.dcm", dicom_slice(4, 4, zeros(32), "0\\0\\0", "s", "1.2.3.4", "1.2.840.10008.1.2.1", kEsc)}}});
    c.push_back(Case{"dicom control bytes in a position", "dcmpos/s.dcm",
                     {{"dcmpos/s.dcm", dicom_slice(4, 4, zeros(32), "1\\" + kEsc)}}});
    c.push_back(Case{"dicom truncated data set", "dcmhead/s.dcm", {{"dcmhead/s.dcm", dicom_slice(4, 4, zeros(32)).substr(0, 200)}}});
    // Voreen .dat (+ raw)
    c.push_back(Case{"voreen overflowing dims", "ov.dat",
                     {{"ov.dat", "ObjectFileName: ov.raw\nResolution: " + big + "\nSliceThickness: 1 1 1\nFormat: UCHAR\n"},
                      {"ov.raw", zeros(100)}}});
    c.push_back(Case{"voreen control bytes", "esc.dat",
                     {{"esc.dat", "ObjectFileName: esc.raw\nResolution: 4 4 4\nSliceThickness: 1 1 1\nFormat: " + kEsc + "\n"},
                      {"esc.raw", zeros(64)}}});
    c.push_back(Case{"voreen infinite spacing", "infsp.dat",
                     {{"infsp.dat", "ObjectFileName: infsp.raw\nResolution: 4 4 4\nSliceThickness: inf 1 1\nFormat: UCHAR\n"},
                      {"infsp.raw", zeros(64)}}});
    c.push_back(Case{"voreen truncated", "tr.dat",
                     {{"tr.dat", "ObjectFileName: tr.raw\nResolution: 16 16 16\nSliceThickness: 1 1 1\nFormat: UCHAR\n"},
                      {"tr.raw", zeros(64)}}});
    // point sets
    add("ply control bytes", "esc.ply", "ply\nformat " + kEsc + " 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", false);
    add("ply overflowing count", "ov.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\n"
        "property float z\nend_header\n" + zeros(12), false);
    add("vtp overflowing count", "ov.vtp",
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n"
        "<Piece NumberOfPoints=\"9223372036854775807\">\n<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
        "format=\"ascii\">0 0 0</DataArray>\n</Points>\n</Piece>\n</PolyData>\n</VTKFile>\n", false);
    add("vts signed extent overflow", "ov.vts",
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"StructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "<StructuredGrid WholeExtent=\"-9223372036854775808 9223372036854775807 0 0 0 0\">\n"
        "<Piece Extent=\"-9223372036854775808 9223372036854775807 0 0 0 0\">\n<Points>\n<DataArray type=\"Float32\" "
        "NumberOfComponents=\"3\" format=\"ascii\">0 0 0</DataArray>\n</Points>\n</Piece>\n</StructuredGrid>\n</VTKFile>\n", false);
    // an array no command uses, its NumberOfComponents no number: refused by info as by the block readers
    add("vts unused array with a bad NumberOfComponents", "badcomp.vts",
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"StructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "<StructuredGrid WholeExtent=\"0 1 0 1 0 1\">\n<Piece Extent=\"0 1 0 1 0 1\">\n<PointData Scalars=\"s\">\n"
        "<DataArray type=\"Float32\" Name=\"s\" format=\"ascii\">0 1 2 3 4 5 6 7</DataArray>\n"
        "<DataArray type=\"Float32\" Name=\"unused\" NumberOfComponents=\"x\" format=\"ascii\">0 1 2 3 4 5 6 7</DataArray>\n"
        "</PointData>\n<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">"
        "0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1</DataArray>\n</Points>\n</Piece>\n</StructuredGrid>\n</VTKFile>\n",
        false);
    {  // .vtu (the nodes of an UnstructuredGrid): one file per defect class
        auto vtu = [](const std::string& attrs, const std::string& np, const std::string& body, const std::string& appended) {
            return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\"" +
                   attrs + ">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"" + np + "\" NumberOfCells=\"0\">\n" + body +
                   "</Piece>\n</UnstructuredGrid>\n" +
                   (appended.empty() ? "" : "<AppendedData encoding=\"raw\">\n_" + appended + "\n</AppendedData>\n") + "</VTKFile>\n";
        };
        const std::string app = "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\n</Points>\n";
        const std::string ascii = "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray>\n</Points>\n";
        add("vtu overflowing count", "ov.vtu", vtu("", "9223372036854775807", ascii, ""), false);
        {  // the file ends 20 bytes into a 48-byte array
            const std::string whole = vtu("", "4", app, u32le(48) + std::string(20, '\1'));
            add("vtu truncated appended data", "tr.vtu", whole.substr(0, whole.find('_', whole.find("<AppendedData")) + 25), false);
        }
        add("vtu bad base64", "b64.vtu",
            vtu("", "4", "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"binary\">MAAA" + kEsc +
                         "</DataArray>\n</Points>\n", ""), false);
        add("vtu compressed block claiming more than it holds", "claim.vtu",
            vtu(" compressor=\"vtkZLibDataCompressor\"", "16000",
                "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\n</Points>\n<!--" +
                    std::string(4000, ' ') + "-->\n",
                u32le(1) + u32le(384000) + u32le(384000) + u32le(1) + "x"), false);
        const std::string bomb = zlib_of(zeros(1 << 20));
        add("vtu decompression bomb", "bomb.vtu",
            vtu(" compressor=\"vtkZLibDataCompressor\"", "4", app,
                u32le(1) + u32le(48) + u32le(48) + u32le(static_cast<std::uint32_t>(bomb.size())) + bomb), false);
        add("vtu missing Points", "nopts.vtu", vtu("", "4", "", ""), false);
    }
    add("vtp control bytes", "esc.vtp",
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + kEsc + "\" version=\"0.1\" byte_order=\"LittleEndian\">\n</VTKFile>\n", false);
    {
        std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (4611686018427387904, 4), }";
        while ((10 + dict.size() + 1) % 64 != 0) dict += ' ';
        dict += '\n';
        const auto len = static_cast<std::uint16_t>(dict.size());
        std::string npy = std::string("\x93NUMPY\x01\x00", 8);
        npy += static_cast<char>(len & 0xff);
        npy += static_cast<char>(len >> 8);
        add("npy overflowing shape", "ov.npy", npy + dict + zeros(48), false);
    }
    return c;
}

// The message without its "meshless COMMAND: " prefix.
std::string words_of(const std::string& m) { return m.substr(std::min(m.size(), m.find(": ") + 2)); }

// Bytes a terminal would interpret: C0 controls other than the message's final newline, DEL.
bool has_control_bytes(const std::string& s) {
    for (std::size_t i = 0; i < s.size(); ++i) {
        const auto ch = static_cast<unsigned char>(s[i]);
        if ((ch < 0x20 && !(ch == '\n' && i + 1 == s.size())) || ch == 0x7f) return true;
    }
    return false;
}

}  // namespace

TEST_CASE("must-fail corpus: every hostile file exits 2 with one clean line naming it, nothing written, bounded memory",
          "[cli][hostile]") {
    TempDir d("hostile");
    const auto cases = corpus();
    REQUIRE(cases.size() >= 50);
    for (const Case& k : cases) {
        for (const auto& [name, bytes] : k.files) {
            fs::create_directories((d.path / name).parent_path());
            spit(d.path / name, bytes);
        }
        const std::string in = (d.path / k.file).string();
        const std::string base = fs::path(k.file).filename() == "index.json" ? fs::path(k.file).parent_path().string()
                                                                             : fs::path(k.file).filename().string();
        const std::string out = (d.path / "out.ply").string();
        // `info` proves the payload as the readers do: every defect, header or payload (a bomb, a
        // truncated or corrupt payload), fails it exactly as it fails the reading command, with the
        // same message (a claim the file cannot hold is a data error before it is a memory one)
        std::vector<std::string> cmds;
        cmds.push_back("MESHLESS info " + in);
        cmds.push_back(k.volume ? "MESHLESS isosurface " + in + " --iso 0.5 -o " + out
                                : "MESHLESS fit " + in + " -o " + (d.path / "out.mlf").string());
        if (k.volume) cmds.push_back("MESHLESS convert " + in + " -o " + (d.path / "out.mlb").string());
        std::vector<std::string> messages;
        for (const auto& cmd : cmds) {
            INFO(k.label << ": " << cmd);
            const RunResult r = sh(cmd, d);
            messages.push_back(r.err);
            INFO("stderr: " << r.err);
            CHECK(r.code == 2);
            CHECK(!r.err.empty());
            CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
            // the file given, or (a header naming its data file) the data file at fault
            bool named = r.err.find(base) != std::string::npos;
            for (const auto& f : k.files) named = named || r.err.find(fs::path(f.first).filename().string()) != std::string::npos;
            CHECK(named);
            CHECK(!has_control_bytes(r.err));
            CHECK(!fs::exists(out));
            CHECK(!fs::exists(d.path / "out.mlf"));
            CHECK(!fs::exists(d.path / "out.mlb"));
            for (const auto& e : fs::directory_iterator(d.path))
                CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
        }
        // and with the reader's words: "meshless info: MSG" and "meshless isosurface: MSG"
        const auto words = [](const std::string& m) { return m.substr(std::min(m.size(), m.find(": ") + 2)); };
        INFO(k.label);
        for (std::size_t c = 1; c < messages.size(); ++c) CHECK(words(messages[0]) == words(messages[c]));
    }
    // every child (and grandchild) the cases ran, its largest resident set: a header's claim must
    // never become resident memory (the bombs claim 4 GiB and more)
    rusage ru{};
    REQUIRE(getrusage(RUSAGE_CHILDREN, &ru) == 0);
#ifdef MESHLESS_SANITIZED
    const long limit_kb = 600 * 1024;  // AddressSanitizer's shadow and quarantine
#else
    const long limit_kb = 200 * 1024;
#endif
    CHECK(ru.ru_maxrss < limit_kb);
}

TEST_CASE("info proves well-formed payloads of every encoding, and the shared volumes, with exit 0", "[cli][hostile]") {
    // the same builders as the must-fail corpus, with payloads that hold what the headers claim
    TempDir d("hostile_ok");
    const std::string plane(16 * 16 * 16, '\x07');
    std::vector<std::pair<std::string, std::string>> files = {
        {"ok_gz.nrrd", nrrd("type: uint8\ndimension: 3\nsizes: 16 16 16\nencoding: gzip\n", gzip_of(plane))},
        {"ok_ascii.nrrd", nrrd("type: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: ascii\n", "1 2 3 4 5 6 7 8\n")},
        {"ok_z.mha", mha("NDims = 3\nDimSize = 16 16 16\nElementType = MET_UCHAR\nCompressedData = True\n", zlib_of(plane))},
        {"ok.vtk", vtk_legacy("16 16 16", "1 1 1", "4096", "STRUCTURED_POINTS", plane)},
        {"ok_ascii.vti", vti("0 1 0 1 0 0", "1 1 1", "0 0 0", "ImageData",
                             "<DataArray type=\"UInt8\" Name=\"s\" format=\"ascii\">\n1 2 3 4\n</DataArray>\n")},
        {"ok_rle.slc", slc("16 16 16", "1 1 1", "1", [] {
             std::string s;
             for (int z = 0; z < 16; ++z) s += "6 X\x7f\x07\x7f\x07\x02\x07";  // 127 + 127 + 2 = 256 bytes a slice
             return s;
         }())},
        {"ok.nii.gz", gzip_of(nifti(16, 16, 16, 1, 0, plane))},
        {"okjs/index.json", vtkjs_index("0,15,0,15,0,15", "1,1,1", "Uint8Array")},
        {"okjs/data/s.gz", gzip_of(plane)},
    };
    {
        // two zlib blocks of 2048 bytes (appended raw), as vtkXMLImageDataWriter writes them
        const std::string block = zlib_of(plane.substr(0, 2048));
        const std::string hdr = u32le(2) + u32le(2048) + u32le(2048) + u32le(static_cast<std::uint32_t>(block.size())) +
                                u32le(static_cast<std::uint32_t>(block.size()));
        files.push_back({"ok_z.vti",
                         "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\" "
                         "compressor=\"vtkZLibDataCompressor\">\n<ImageData WholeExtent=\"0 15 0 15 0 15\" Origin=\"0 0 0\" "
                         "Spacing=\"1 1 1\">\n<Piece Extent=\"0 15 0 15 0 15\">\n<PointData Scalars=\"s\">\n<DataArray "
                         "type=\"UInt8\" Name=\"s\" format=\"appended\" offset=\"0\"/>\n</PointData>\n</Piece>\n</ImageData>\n"
                         "<AppendedData encoding=\"raw\">\n_" + hdr + block + block + "\n</AppendedData>\n</VTKFile>\n"});
    }
    std::vector<std::string> inputs;
    for (const auto& [name, bytes] : files) {
        fs::create_directories((d.path / name).parent_path());
        spit(d.path / name, bytes);
        if (name.find("/data/") == std::string::npos) inputs.push_back((d.path / name).string());
    }
    for (const char* rel : {"vtk_headsq/quarter.nhdr", "vtk_HeadMRVolume/HeadMRVolume.mhd", "vtk_slc/embryo.slc",
                                   "vtk_hydrogen/hydrogen.vti", "vtk_ironProt/ironProt.vtk",
                                   "mni152_brain/avg152T1_RL_nifti.nii.gz", "vtkjs_LIDC2/LIDC2.vti",
                                   "fuel/fuel_64x64x64_uint8.raw"}) {
        const fs::path p = shared_data() / rel;
        if (fs::exists(p)) inputs.push_back(p.string());
    }
    for (const std::string& in : inputs) {
        INFO(in);
        const RunResult r = sh("MESHLESS info " + in, d);
        INFO("stderr: " << r.err);
        CHECK(r.code == 0);
        CHECK(r.out.find("payload: checked") != std::string::npos);
    }
    // one byte short of the compressed payload: refused (the proof decodes, it does not trust the sizes)
    const std::string gz = gzip_of(plane.substr(0, plane.size() - 1));
    spit(d.path / "short_gz.nrrd", nrrd("type: uint8\ndimension: 3\nsizes: 16 16 16\nencoding: gzip\n", gz));
    const RunResult r = sh("MESHLESS info " + (d.path / "short_gz.nrrd").string(), d);
    CHECK(r.code == 2);
    CHECK(r.err.find("short_gz.nrrd") != std::string::npos);
}

namespace {
// A meshless stream header (formats/point_stream.hpp): magic, version 1, kind, record size, flags 0.
std::string stream_header(std::uint32_t kind, std::uint32_t record_size) {
    std::string h("\x89MLS\r\n\x1a\n", 8);
    h += u32le(1) + u32le(kind) + u32le(record_size) + zeros(12);
    return h;
}
// A frame header: type, flags, 8 reserved bytes, record count, payload bytes, CRC-32 of the payload.
std::string frame(std::uint32_t type, std::uint32_t flags, std::uint64_t count, std::uint32_t bytes, const std::string& payload) {
    std::string f = u32le(type) + u32le(flags) + zeros(8);
    f += u32le(static_cast<std::uint32_t>(count)) + u32le(static_cast<std::uint32_t>(count >> 32));
    f += u32le(bytes) + u32le(meshless::crc32_ieee(0, payload.data(), payload.size()));
    return f + payload;
}
}  // namespace

TEST_CASE("stream frames that claim more than they hold take no memory for the claim", "[cli][hostile]") {
#ifdef MESHLESS_SANITIZED
    WARN("an address-space limit and AddressSanitizer's shadow do not mix: skipped in the sanitizer tier");
    return;
#endif
    TempDir d("hostile_stream");
    const std::uint32_t kGiB = 1u << 30;
    // 8 MiB of zeros, compressed: a real zstd payload, its frame claiming 1 GiB of records
    const std::string plain(std::size_t{8} << 20, '\0');
    std::string z(ZSTD_compressBound(plain.size()), '\0');
    z.resize(ZSTD_compress(z.data(), z.size(), plain.data(), plain.size(), 1));
    const std::vector<std::pair<std::string, std::string>> streams = {
        {"meta_claim.mlp", stream_header(1, 32) + frame(1, 0, 0, kGiB, "").substr(0, 32)},
        {"unknown_claim.mlp", stream_header(1, 32) + frame(9, 0, 0, kGiB, "").substr(0, 32) + zeros(100)},
        {"raw_claim.mlp", stream_header(1, 32) + frame(2, 0, kGiB / 32, kGiB, "").substr(0, 32) + zeros(1000)},
        {"zstd_claim.mlp", stream_header(1, 32) + frame(2, 1, kGiB / 32, static_cast<std::uint32_t>(z.size()), z)},
    };
    for (const auto& [name, bytes] : streams) {
        spit(d.path / name, bytes);
        const std::string in = (d.path / name).string(), out = (d.path / "out.ply").string();
        // an address space of 400 MB: a 1 GiB buffer taken on the header's word fails as "out of memory"
        for (const std::string& cmd : std::vector<std::string>{"ulimit -v 400000; MESHLESS info " + in,
                                                               "ulimit -v 400000; MESHLESS write -o " + out + " < " + in}) {
            INFO(cmd);
            const RunResult r = sh(cmd, d);
            INFO("stderr: " << r.err);
            CHECK(r.code == 2);
            CHECK((r.err.find("truncated") != std::string::npos || r.err.find("corrupt") != std::string::npos));
            CHECK(r.err.find("out of memory") == std::string::npos);
            CHECK(!fs::exists(out));
        }
    }
}

TEST_CASE("a FIFO given as an input file is refused at once and not waited on", "[cli][hostile]") {
    // opening a FIFO for reading blocks until a writer comes: every command, and every file a
    // header names, must refuse it instead (exit 2, the path named); `timeout` turns a hang into 124
    TempDir d("hostile_fifo");
    for (const char* name : {"pipe.nrrd", "pipe.raw", "pipe.ply", "pipe.mlb", "pipe.mls", "pipe.mlf", "pipe.vtp", "pipe.tf"})
        REQUIRE(::mkfifo((d.path / name).c_str(), 0600) == 0);
    spit(d.path / "named.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: pipe.raw\n\n");
    const std::string p = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "sphere", meshless::AnalyticField::sphere, 8, 100, 0);
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"MESHLESS info " + p + "pipe.nrrd", "pipe.nrrd"},
        {"MESHLESS info " + p + "pipe.mlb", "pipe.mlb"},
        {"MESHLESS info " + p + "pipe.mlf", "pipe.mlf"},
        {"MESHLESS isosurface " + p + "pipe.raw --dims 2,2,2 --type uint8 --iso 1 -o " + p + "o.ply", "pipe.raw"},
        {"MESHLESS isosurface " + p + "named.nhdr --iso 1 -o " + p + "o.ply", "pipe.raw"},
        {"MESHLESS extract " + p + "pipe.mls --iso 1 -o " + p + "o.ply", "pipe.mls"},
        {"MESHLESS splat " + p + "pipe.ply -o " + p + "o.png", "pipe.ply"},
        {"MESHLESS fit " + p + "pipe.vtp -o " + p + "o.mlf", "pipe.vtp"},
        {"MESHLESS render " + vol + " --tf " + p + "pipe.tf -o " + p + "o.png", "pipe.tf"},
    };
    for (const auto& [cmd, named] : cases) {
        INFO(cmd);
        const RunResult r = sh("timeout 20 " + cmd, d);
        INFO("stderr: " << r.err);
        CHECK(r.code == 2);
        CHECK(r.err.find(named + ": not a regular file (a FIFO") != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
}

TEST_CASE("a point set that merges into fewer than 4 points is a data error naming the file", "[cli][hostile]") {
    // 100 rows at 3 positions: they merge into 3 points (the mpu field needs 4); a set spread over
    // 1e-298 units merged into one through an undefined conversion (a subnormal hash cell made its
    // index NaN: UBSan found it) and now is 35 distinct points, as it should
    TempDir d("hostile_merge");
    std::string csv = "x,y,z,value\n";
    for (int i = 0; i < 100; ++i) csv += std::to_string(i % 3) + "," + std::to_string(2 * (i % 3)) + ",0," + std::to_string(i) + "\n";
    std::string tiny = "x,y,z,value\n";
    for (int i = 0; i < 100; ++i)
        tiny += std::to_string(i % 7) + "e-300," + std::to_string(i % 5) + "e-300," + std::to_string(i % 3) + "e-300," +
                std::to_string(i) + "\n";
    spit(d.path / "subnormal.csv", tiny);
    CHECK(sh("MESHLESS fit " + (d.path / "subnormal.csv").string() + " -o " + (d.path / "s.mlf").string(), d).code == 0);
    spit(d.path / "tiny.csv", csv);
    const std::string in = (d.path / "tiny.csv").string();
    for (const std::string& cmd : std::vector<std::string>{"MESHLESS fit " + in + " -o " + (d.path / "o.mlf").string(),
                                                           "MESHLESS probe " + in + " --at 0,0,0"}) {
        INFO(cmd);
        const RunResult r = sh(cmd, d);
        INFO("stderr: " << r.err);
        CHECK(r.code == 2);  // was 1, a usage error, for what is the data's fault
        CHECK_THAT(r.err, Catch::Contains("tiny.csv: mpu: ") && Catch::Contains("distinct points"));
    }
}

TEST_CASE("a stream whose recorded isovalue is not finite is refused by the stages with the stream named", "[cli][hostile]") {
    TempDir d("hostile_meta");
    const std::string vol = write_uint8_analytic_volume(d, "sphere", meshless::AnalyticField::sphere, 16, 100, 0);
    const std::string good = (d.path / "good.mls").string();
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 > " + good, d).code == 0);
    std::string s = slurp(good);
    // the META frame (type 1) follows the 32-byte header: its `iso=` line rewritten, its CRC renewed
    REQUIRE(s.size() > 64);
    REQUIRE(s[32] == 1);
    std::uint32_t bytes = 0;
    std::memcpy(&bytes, s.data() + 32 + 24, 4);
    std::string meta = s.substr(64, bytes);
    const std::size_t at = meta.find("\niso=");
    REQUIRE(at != std::string::npos);
    for (const std::string bad : {"nan", "inf", "-inf"}) {
        std::string m = meta;
        m.replace(at + 5, m.find('\n', at + 1) - (at + 5), bad);
        std::string t = s.substr(0, 64 + 24 - 32) + u32le(static_cast<std::uint32_t>(m.size())) +
                        u32le(meshless::crc32_ieee(0, m.data(), m.size())) + m + s.substr(64 + bytes);
        spit(d.path / "bad.mls", t);
        const RunResult r = sh("MESHLESS project < " + (d.path / "bad.mls").string() + " | MESHLESS write -o " + (d.path / "o.ply").string(), d);
        INFO("iso=" << bad << " stderr: " << r.err);
        CHECK(r.code == 2);
        CHECK_THAT(r.err, Catch::Contains("-: stream metadata: 'iso' is not a finite number: " + bad));
        CHECK_FALSE(fs::exists(d.path / "o.ply"));
    }
}

namespace {

// Lines of `text` that hold `needle`.
std::vector<std::string> lines_with(const std::string& text, const std::string& needle) {
    std::vector<std::string> r;
    std::size_t b = 0;
    while (b < text.size()) {
        std::size_t e = text.find('\n', b);
        if (e == std::string::npos) e = text.size();
        const std::string line = text.substr(b, e - b);
        if (line.find(needle) != std::string::npos) r.push_back(line);
        b = e + 1;
    }
    return r;
}

std::string nrrd_header(const std::string& data_file) {
    return "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: " + data_file + "\n\n";
}

}  // namespace

TEST_CASE("references out of the archive: batch refuses each input, writes nothing for it and goes on, and info names "
          "every file resolved", "[cli][hostile]") {
    TempDir d("hostile-refs");
    const fs::path arch = d.path / "archive", secret = d.path / "secret";
    fs::create_directories(arch / "js");
    fs::create_directories(secret);
    // the bytes a header must never carry into an output: 64 distinct values no good volume holds
    std::string secret_bytes;
    for (int i = 0; i < 64; ++i) secret_bytes += static_cast<char>(150 + i);
    spit(secret / "s.raw", secret_bytes);
    spit(secret / "evil_4x4x4_uint8.raw", secret_bytes);
    spit(secret / "p.img", secret_bytes);
    // the classes: absolute and `..` references in each header format, a reference through a
    // symbolic link in the archive, a symbolic link as the input itself
    spit(arch / "abs.nhdr", nrrd_header((secret / "s.raw").string()));
    spit(arch / "dotdot.nhdr", nrrd_header("../secret/s.raw"));
    spit(arch / "list.nhdr", nrrd_header("LIST\ns.raw\n../secret/s.raw"));  // one good-looking name, one not
    spit(arch / "s.raw", zeros(32));
    spit(arch / "meta.mhd", "ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\nElementDataFile = ../secret/s.raw\n");
    spit(arch / "voreen.dat", "ObjectFileName: " + (secret / "s.raw").string() + "\nResolution: 4 4 4\nFormat: UCHAR\n");
    spit(arch / "js" / "index.json",
         "{\"vtkClass\":\"vtkImageData\",\"extent\":[0,3,0,3,0,3],\"spacing\":[1,1,1],\"origin\":[0,0,0],\"pointData\":{"
         "\"arrays\":[{\"data\":{\"dataType\":\"Uint8Array\",\"numberOfComponents\":1,\"ref\":{\"id\":\"s.raw\",\"basepath\":"
         "\"../../secret\",\"encode\":\"LittleEndian\",\"registration\":\"setScalars\"}}}]}}");
    fs::create_directory_symlink("../secret", arch / "linkdir");
    spit(arch / "vialink.nhdr", nrrd_header("linkdir/s.raw"));
    fs::create_symlink("../secret/evil_4x4x4_uint8.raw", arch / "evil_4x4x4_uint8.raw");
    {
        std::string h = nifti(4, 4, 4, 1, 0, "").substr(0, 348);
        std::memcpy(h.data() + 344, "ni1\0", 4);
        const float zero = 0;
        std::memcpy(h.data() + 108, &zero, 4);  // vox_offset 0 in the .img
        spit(arch / "pair.hdr", h);
        fs::create_symlink("../secret/p.img", arch / "pair.img");
    }
    // a well-formed volume of the archive, done as usual
    std::string good(4 * 4 * 4, '\0');
    for (std::size_t i = 0; i < good.size(); ++i) good[i] = static_cast<char>(i % 4 < 2 ? 10 : 90);
    spit(arch / "good_4x4x4_uint8.raw", good);

    const fs::path out = d.path / "out";
    const RunResult r = sh("MESHLESS batch " + arch.string() + " -o " + out.string() + " --iso 50 --formats ply,stream", d);
    INFO(r.out << r.err);
    CHECK(r.code == 2);
    // s.raw: a headerless raw file that voreen.dat names by its file name, so that .dat describes it
    // and sends its reader to the secret too
    const std::vector<std::string> refused = {"abs", "dotdot", "list", "meta", "voreen", "js", "vialink", "evil_4x4x4_uint8",
                                              "pair", "s"};
    for (const auto& name : refused) {
        INFO(name);
        std::vector<std::string> rows;  // the table's row of this volume
        for (const auto& line : lines_with(r.out, name + " "))
            if (line.rfind(name + " ", 0) == 0) rows.push_back(line);
        REQUIRE(rows.size() == 1);
        CHECK(rows[0].find("REFUSED") != std::string::npos);
        CHECK(rows[0].find("outside the archive folder") != std::string::npos);
        CHECK(!fs::exists(out / (name + ".mlb")));
        CHECK(!fs::exists(out / (name + "_iso50.ply")));
    }
    CHECK(lines_with(r.out, "good_4x4x4_uint8 ").at(0).find("done") != std::string::npos);
    CHECK(fs::exists(out / "good_4x4x4_uint8.mlb"));
    CHECK(r.out.find(std::to_string(refused.size()) + " refused") != std::string::npos);
    for (const auto& line : lines_with(r.err, "refused")) CHECK(!has_control_bytes(line));
    // no byte of the secret in anything written
    for (const auto& e : fs::recursive_directory_iterator(out)) {
        if (!e.is_regular_file()) continue;
        INFO(e.path());
        CHECK(slurp(e.path()).find(secret_bytes.substr(0, 16)) == std::string::npos);
    }

    // the other commands follow references as the formats allow, and info says where each leads
    const RunResult i = sh("MESHLESS info " + (arch / "dotdot.nhdr").string(), d);
    INFO(i.out << i.err);
    CHECK(i.code == 0);
    CHECK(i.out.find("-> " + fs::weakly_canonical(secret / "s.raw").string()) != std::string::npos);
    const RunResult v = sh("MESHLESS info " + (arch / "vialink.nhdr").string(), d);
    CHECK(v.code == 0);
    CHECK(v.out.find("linkdir/s.raw -> " + fs::weakly_canonical(secret / "s.raw").string()) != std::string::npos);
}

TEST_CASE("the gzip tail rule: info, isosurface, convert, sample and mc agree on what may follow a gzip payload",
          "[cli][hostile]") {
    TempDir d("hostile-gzip-tail");
    const std::string fields = "type: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\n";
    std::string plain;
    for (int i = 0; i < 64; ++i) plain += static_cast<char>(i);
    const std::string member = gzip_of(plain);
    const auto commands = [&](const std::string& in) {
        return std::vector<std::string>{
            "MESHLESS info " + in,
            "MESHLESS isosurface " + in + " --iso 20.5 -o " + (d.path / "o.ply").string(),
            "MESHLESS convert " + in + " -o " + (d.path / "o.mlb").string(),
            "MESHLESS sample " + in + " --count 10 -o " + (d.path / "o_s.ply").string(),
            "MESHLESS mc " + in + " --iso 20.5 -o " + (d.path / "o_mc.ply").string(),
        };
    };
    // refused everywhere, in the same words: a second member, the magic of one, a member that decodes to more
    for (const auto& [name, payload] : std::vector<std::pair<std::string, std::string>>{
             {"second.nrrd", member + gzip_of("x")},
             {"magic.nrrd", member + "\x1f\x8b"},
             {"empty_member.nrrd", member + gzip_of("")},
             {"longer.nrrd", gzip_of(plain + "x")}}) {
        spit(d.path / name, nrrd(fields, payload));
        std::vector<std::string> messages;
        for (const std::string& cmd : commands((d.path / name).string())) {
            INFO(cmd);
            const RunResult r = sh(cmd, d);
            INFO("stderr: " << r.err);
            CHECK(r.code == 2);
            CHECK(r.err.find(name + ": compressed data decompresses to more than 64 bytes") != std::string::npos);
            messages.push_back(words_of(r.err));
        }
        for (const auto& m : messages) CHECK(m == messages.front());
    }
    // other padding is accepted everywhere
    for (const auto& [name, payload] : std::vector<std::pair<std::string, std::string>>{
             {"zero.nrrd", member + std::string(1, '\0')}, {"pad.nrrd", member + "padding\n"}, {"one_1f.nrrd", member + "\x1f"}}) {
        spit(d.path / name, nrrd(fields, payload));
        for (const std::string& cmd : commands((d.path / name).string())) {
            INFO(cmd);
            const RunResult r = sh(cmd, d);
            INFO("stderr: " << r.err);
            CHECK(r.code == 0);
        }
    }
}

TEST_CASE("a brick store whose header puts samples beyond float32 is refused by verify, info and isosurface",
          "[cli][hostile]") {
    TempDir d("hostile-mlb-origin");
    spit(d.path / "v_4x4x4_uint8.raw", std::string(64, '\x07'));
    const std::string mlb = (d.path / "far.mlb").string();
    REQUIRE(sh("MESHLESS convert " + (d.path / "v_4x4x4_uint8.raw").string() + " -o " + mlb, d).code == 0);
    REQUIRE(sh("MESHLESS verify " + mlb, d).code == 0);
    std::string bytes = slurp(mlb);
    REQUIRE(bytes.size() > 256);
    const double far = 1e308;  // header: magic, version, size, dims[3], then origin[3] at byte 40
    std::memcpy(bytes.data() + 40, &far, 8);
    const std::uint32_t crc = meshless::crc32_ieee(0, bytes.data(), 252);  // the header's CRC-32 of bytes [0, 252)
    std::memcpy(bytes.data() + 252, &crc, 4);
    spit(mlb, bytes);
    for (const std::string& cmd : {"MESHLESS verify " + mlb, "MESHLESS info " + mlb,
                                   "MESHLESS isosurface " + mlb + " --iso 3 -o " + (d.path / "o.ply").string()}) {
        INFO(cmd);
        const RunResult r = sh(cmd, d);
        INFO("stderr: " << r.err);
        CHECK(r.code == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK(r.err.find("far.mlb") != std::string::npos);
        CHECK(r.err.find("float32") != std::string::npos);
    }
    CHECK(!fs::exists(d.path / "o.ply"));
}

TEST_CASE("info - on a point or sample stream without its END frame fails as the stream's readers do", "[cli][hostile]") {
    TempDir d("hostile-stream-end");
    spit(d.path / "v_8x8x8_uint8.raw", [] {
        std::string v;
        for (int k = 0; k < 8; ++k)
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) v += static_cast<char>((i + j + k) * 10);
        return v;
    }());
    const std::string vol = (d.path / "v_8x8x8_uint8.raw").string();
    const std::string samples = (d.path / "s.mls").string(), points = (d.path / "p.mls").string();
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 > " + samples, d).code == 0);
    REQUIRE(sh("MESHLESS project < " + samples + " > " + points, d).code == 0);
    for (const auto& [whole, reader] : std::vector<std::pair<std::string, std::string>>{
             {samples, "MESHLESS project"}, {points, "MESHLESS write -o " + (d.path / "o.ply").string()}}) {
        const std::string bytes = slurp(whole);
        REQUIRE(sh("MESHLESS info - < " + whole, d).code == 0);
        // the END frame (a 32-byte frame header and no payload, docs/formats.md) is the stream's last bytes
        REQUIRE(bytes.size() > 64);
        const std::size_t cut = bytes.size() - 32;
        spit(d.path / "cut.mls", bytes.substr(0, cut));
        const std::string in = (d.path / "cut.mls").string();
        const RunResult i = sh("MESHLESS info - < " + in, d);
        const RunResult r = sh(reader + " < " + in + " > " + (d.path / "out.bin").string(), d);
        INFO(whole << ": info: " << i.err << "reader: " << r.err);
        CHECK(i.code == 2);
        CHECK(r.code == 2);
        CHECK(std::count(i.err.begin(), i.err.end(), '\n') == 1);
        CHECK(!has_control_bytes(i.err));
        CHECK(words_of(i.err) == words_of(r.err));
    }
    CHECK(!fs::exists(d.path / "o.ply"));
}

TEST_CASE("splat drops the PLY points it cannot draw, counts them and warns, as it does for a VTP", "[cli][hostile]") {
    TempDir d("hostile-splat-nan");
    spit(d.path / "v_8x8x8_uint8.raw", [] {
        std::string v;
        for (int k = 0; k < 8; ++k)
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) v += static_cast<char>((i + j + k) * 10);
        return v;
    }());
    const std::string ply = (d.path / "p.ply").string();
    REQUIRE(sh("MESHLESS isosurface " + (d.path / "v_8x8x8_uint8.raw").string() + " --iso 50.5 -o " + ply, d).code == 0);
    std::string bytes = slurp(ply);
    const std::size_t body = bytes.find("end_header\n") + 11;
    REQUIRE((bytes.size() - body) % 32 == 0);
    REQUIRE((bytes.size() - body) / 32 >= 4);
    const float nan = std::nanf(""), inf = INFINITY;
    std::memcpy(bytes.data() + body + 0 * 32 + 4, &nan, 4);       // record 0: y is NaN
    std::memcpy(bytes.data() + body + 2 * 32 + 12 + 8, &inf, 4);  // record 2: nz is infinite
    const std::string bad = (d.path / "nan.ply").string();
    spit(bad, bytes);
    // with bounds recorded (streamed), with a spool (a turntable), and as EWA (two passes)
    for (const std::string& extra : {std::string(), std::string(" --turntable 2"), std::string(" --kernel ewa")}) {
        const std::string png = (d.path / "o.png").string();
        const RunResult r = sh("MESHLESS splat " + bad + " -o " + png + " --size 64x64" + extra, d);
        INFO(extra << ": " << r.err);
        CHECK(r.code == 0);
        CHECK(r.err.find("nan.ply: 2 points with a non-finite position, normal, radius or value") != std::string::npos);
        // said once (a turntable also reports its frames)
        std::size_t warnings = 0;
        for (std::size_t at = 0; (at = r.err.find("warning", at)) != std::string::npos; ++at) ++warnings;
        CHECK(warnings == 1);
    }
    const RunResult ok = sh("MESHLESS splat " + ply + " -o " + (d.path / "ok.png").string() + " --size 64x64", d);
    CHECK(ok.code == 0);
    CHECK(ok.err.empty());
}

TEST_CASE("unbounded parameters: refused before any work with exit 1 and one line naming the option, nothing written",
          "[cli][hostile]") {
    TempDir d("hostile-params");
    // 197 points on a sphere (the size of the set that made --alpha 100 take gigabytes) and 150000
    // (where --alpha 4 implies more than the 512 MiB address space the case allows)
    const auto points = [](int n) {
        std::string csv = "x,y,z,v\n";
        for (int k = 0; k < n; ++k) {
            const double z = 1 - 2 * (k + 0.5) / n, r = std::sqrt(1 - z * z), phi = k * 2.399963229728653;
            csv += std::to_string(r * std::cos(phi)) + "," + std::to_string(r * std::sin(phi)) + "," + std::to_string(z) + "," +
                   std::to_string(z) + "\n";
        }
        return csv;
    };
    spit(d.path / "p197.csv", points(197));
    spit(d.path / "p150k.csv", points(150000));
    spit(d.path / "v_8x8x8_uint8.raw", std::string(512, '\x07'));
    const std::string p197 = (d.path / "p197.csv").string(), p150k = (d.path / "p150k.csv").string();
    const std::string vol = (d.path / "v_8x8x8_uint8.raw").string();
    const std::string out = (d.path / "out").string();
    struct Param {
        std::string cmd, option;
    };
    const std::vector<Param> cases = {
        {"MESHLESS fit " + p197 + " --field mpu --alpha 100 -o " + out + ".mlf", "--alpha"},
        {"MESHLESS fit " + p197 + " --field mpu --alpha 1e6 -o " + out + ".mlf", "--alpha"},
        {"MESHLESS fit " + p197 + " --field mpu --alpha 0.5 -o " + out + ".mlf", "--alpha"},
        {"MESHLESS fit " + p197 + " --field mpu --alpha nan -o " + out + ".mlf", "--alpha"},
        {"MESHLESS probe " + p197 + " --field mpu --alpha 100 --at 0,0,0", "--alpha"},
        {"ulimit -v 524288; MESHLESS fit " + p150k + " --field mpu --alpha 4 -o " + out + ".mlf", "--alpha 4"},
        {"ulimit -v 2097152; MESHLESS splat " + p197 + " --size 16384x16384 -o " + out + ".png", "--size 16384x16384"},
        {"ulimit -v 2097152; MESHLESS demo --size 16384x16384 -o " + out + "_demo", "--size 16384x16384"},
        {"ulimit -v 524288; MESHLESS slice " + p197 + " --plane z=0 --size 16384x16384 -o " + out + ".png", "--size 16384x16384"},
        {"MESHLESS slice " + p197 + " --plane z=0 --size 16385x16 -o " + out + ".png", "--size"},
        {"ulimit -v 2097152; MESHLESS isosurface " + p197 + " --iso 0 --max-cells 2147483648 -o " + out + ".ply", "--max-cells"},
        {"MESHLESS isosurface " + p197 + " --iso 0 --max-cells 4294967296 -o " + out + ".ply", "--max-cells"},
        {"MESHLESS hierarchy " + p197 + " --neighbours 100000 -o " + out + ".mlh", "--neighbours"},
        {"MESHLESS sample " + vol + " --count 100000000000000 -o " + out + ".ply", "--count 100000000000000"},
        {"MESHLESS isosurface " + vol + " --spacing 1e308,1,1 --iso 3 -o " + out + ".ply", "--spacing"},
        {"MESHLESS isosurface " + vol + " --spacing inf,1,1 --iso 3 -o " + out + ".ply", "--spacing"},
        // each spacing within float32, the samples it puts (8 of them) beyond it: the option's fault
        {"MESHLESS isosurface " + vol + " --spacing 3e38,1,1 --iso 3 -o " + out + ".ply", "--spacing"},
        {"MESHLESS info " + vol + " --spacing 1,1e38,1", "--spacing"},
        {"MESHLESS hierarchy " + p197 + " --max-splits 99999999999999999999 -o " + out + ".mlh", "--max-splits"},
        {"MESHLESS hierarchy " + p197 + " --max-splits -99999999999999999999 -o " + out + ".mlh", "--max-splits"},
        {"MESHLESS fit " + p197 + " --field rbf-grid --binning 1e-9 -o " + out + ".mlf", "--binning"},
        {"ulimit -v 2097152; MESHLESS render " + vol + " --size 16384x16384 -o " + out + ".png", "--size 16384x16384"},
        {"MESHLESS isosurface " + vol + " --radius-scale 1e300 --iso 3 -o " + out + ".ply", "--radius-scale"},
    };
    for (const auto& c : cases) {
#ifdef MESHLESS_SANITIZED
        // an address-space limit and AddressSanitizer's shadow do not mix: the cases refused for the
        // memory ulimit -v leaves run in the Release tier only
        if (c.cmd.rfind("ulimit -v", 0) == 0) continue;
#endif
        INFO(c.cmd);
        const auto t0 = std::chrono::steady_clock::now();
        const RunResult r = sh(c.cmd, d);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        INFO("stderr: " << r.err);
        CHECK(r.code == 1);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK(r.err.find(c.option) != std::string::npos);
        CHECK(!has_control_bytes(r.err));
        CHECK(seconds < 10);  // up front: no fit, no image (the 150000 points are read first)
        for (const char* ext : {".mlf", ".png", ".ply", ".mlh"}) CHECK(!fs::exists(out + ext));
        for (const auto& e : fs::directory_iterator(d.path)) CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
    }
#ifndef MESHLESS_SANITIZED
    // sample streams its points: a count far beyond a 1 GiB address space is written, not refused
    const RunResult r = sh("ulimit -v 1048576; MESHLESS sample " + vol + " --count 40000000 -o " + out + ".ply", d);
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(fs::file_size(out + ".ply") > 40000000ull * 32);
    fs::remove(out + ".ply");
#endif
}

TEST_CASE("every numeric option's --help states the range it is checked against", "[cli][hostile]") {
    TempDir d("hostile-help-ranges");
    const RunResult top = sh("MESHLESS --help", d);
    REQUIRE(top.code == 0);
    // the commands: the lines "  NAME   what it does" between "commands:" and the blank line after them
    std::vector<std::string> commands;
    {
        std::istringstream in(top.out.substr(top.out.find("commands:")));
        std::string line;
        std::getline(in, line);
        while (std::getline(in, line) && !line.empty())
            if (line.size() > 2 && line[2] != ' ') commands.push_back(line.substr(2, line.find(' ', 2) - 2));
    }
    REQUIRE(commands.size() >= 20);
    // metavars of one number (letters the options use for counts, sizes and factors; not V, an
    // isovalue, nor DEG, an angle: any finite number)
    const std::set<std::string> numeric = {"N", "K", "B", "L", "M", "S", "E", "F", "G", "C", "A", "D", "Z", "CELLS", "WxH"};
    const std::regex option(R"(^  (?:-\w, )?--([\w-]+) (\S+)(?:\s+(.*))?$)");
    const std::regex range(R"(\d\.\.-?\d|[<>]=? ?-?\d|[\[(]-?[\d.e+]+, ?[\d.e+^]+[\])]|any integer)");
    int checked = 0;
    for (const std::string& c : commands) {
        const RunResult h = sh("MESHLESS " + c + " --help", d);
        REQUIRE(h.code == 0);
        // each option with its help, continuation lines joined
        std::vector<std::array<std::string, 3>> opts;
        std::istringstream in(h.out);
        std::string line;
        bool in_options = false;
        while (std::getline(in, line)) {
            if (line == "options:") in_options = true;
            if (!in_options) continue;
            std::smatch m;
            if (std::regex_match(line, m, option)) opts.push_back({m[1].str(), m[2].str(), m[3].str()});
            else if (!opts.empty() && line.rfind("      ", 0) == 0) opts.back()[2] += " " + line.substr(line.find_first_not_of(' '));
            else if (line.empty()) in_options = false;
        }
        for (const auto& [name, metavar, help] : opts) {
            if (!numeric.count(metavar) || help.find(" | ") != std::string::npos) continue;  // an enumeration
            INFO("meshless " << c << " --" << name << " " << metavar << ": " << help);
            CHECK(std::regex_search(help, range));
            ++checked;
        }
    }
    CHECK(checked >= 60);
}
