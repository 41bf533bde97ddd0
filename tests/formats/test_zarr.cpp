// Zarr v2 stores as volumes (formats/zarr.hpp), written here by tests/zarr_test_data.hpp against the
// analytic oracle value(i, j, k) = i + 5 j + 20 k on a 13 x 11 x 9 grid whose chunks do not divide
// it (edge chunks): every dtype in both byte orders, C and F order, each compressor (none, zlib,
// gzip, zstd, blosc), both dimension separators; missing chunks read as fill_value (a number, NaN); OME-Zarr level 0 with its scale and translation and
// leading axes of size 1; info's description; and one must-fail store per defect class.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "error_of.hpp"
#include "formats/volume_reader.hpp"
#include "formats/zarr.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"
#include "zarr_test_data.hpp"

using namespace meshless;
using meshless::test::error_of;
using meshless::test::TempDir;
using meshless::test::write_ome_zarr;
using meshless::test::write_zarr;
using meshless::test::zarr_compress;
using meshless::test::zarr_put;
using meshless::test::ZarrWriteOptions;
using Catch::Matchers::Contains;

namespace {

constexpr std::int64_t NX = test::kZarrNx, NY = test::kZarrNy, NZ = test::kZarrNz;

std::vector<double> oracle_values() { return test::zarr_oracle_values(); }

std::vector<double> samples_of(const Volume& v) {
    std::vector<double> out;
    visit_samples(v.view(), [&](const auto* p) {
        for (std::int64_t i = 0; i < v.grid.voxel_count(); ++i) out.push_back(static_cast<double>(p[i]));
    });
    return out;
}

// A valid one-chunk uint8 store of 4x4x2 whose .zarray is `zarray` (a JSON text), with `chunk` as 0.0.0.
std::string store(const TempDir& d, const std::string& name, const std::string& zarray, const std::string& chunk = "") {
    const auto dir = d.path / name;
    zarr_put(dir / ".zarray", zarray);
    if (!chunk.empty()) zarr_put(dir / "0.0.0", chunk);
    return dir.string();
}

std::string zarray(const std::string& shape, const std::string& chunks, const std::string& dtype = "|u1",
                   const std::string& compressor = "null", const std::string& more = "") {
    return "{\"zarr_format\": 2, \"shape\": " + shape + ", \"chunks\": " + chunks + ", \"dtype\": \"" + dtype +
           "\", \"compressor\": " + compressor + ", \"fill_value\": 0, \"filters\": null, \"order\": \"C\"" + more + "}";
}

}  // namespace

TEST_CASE("zarr: every dtype, order, compressor and separator reads the oracle, edge chunks included", "[formats][zarr]") {
    TempDir d("zarr-matrix");
    const std::vector<double> values = oracle_values();
    const char* dtypes[] = {"|u1", "<i2", ">i2", "<u2", ">u2", "<f4", ">f4", "<i4", ">u4", "<f8", ">f8"};
    const char* compressors[] = {"none", "zlib", "gzip", "zstd", "blosc"};
    int n = 0;
    for (const char* dt : dtypes)
        for (const char* c : compressors) {
            ZarrWriteOptions o;
            o.dtype = dt;
            o.compressor = c;
            o.chunks = {4, 5, 6};
            o.fortran = (n % 2) == 1;
            o.separator = (n % 3) == 2 ? '/' : '.';
            const auto dir = d.path / ("s" + std::to_string(n++) + ".zarr");
            write_zarr(dir, values, NX, NY, NZ, o);
            INFO(dt << " " << c << (o.fortran ? " F" : " C") << " separator " << o.separator);
            const Volume v = read_volume(dir.string());
            CHECK(v.grid.dims == std::array<std::int64_t, 3>{NX, NY, NZ});
            CHECK(samples_of(v) == values);
            const std::string t = std::string(dt).substr(1);
            const SampleType want = t == "u1" ? SampleType::u8 : t == "i1" || t == "i2" ? SampleType::i16 : t == "u2" ? SampleType::u16 : SampleType::f32;
            CHECK(v.type == want);
            // the .zarray itself names the store too
            CHECK(read_volume((dir / ".zarray").string()).grid.dims == v.grid.dims);
        }
}

TEST_CASE("zarr: nested chunk folders are found when .zarray names no dimension_separator", "[formats][zarr]") {
    TempDir d("zarr-nested");
    ZarrWriteOptions o;
    o.separator = '/';
    o.chunks = {4, 5, 6};
    o.compressor = "zlib";
    write_zarr(d.path / "n.zarr", oracle_values(), NX, NY, NZ, o);
    std::string za = meshless::test::slurp_file(d.path / "n.zarr" / ".zarray");
    za.erase(za.find("\"dimension_separator\""), std::string("\"dimension_separator\": \"/\",\n  ").size());
    zarr_put(d.path / "n.zarr" / ".zarray", za);
    CHECK(za.find("dimension_separator") == std::string::npos);
    CHECK(samples_of(read_volume((d.path / "n.zarr").string())) == oracle_values());
}

TEST_CASE("zarr: missing chunks read as fill_value, NaN included", "[formats][zarr]") {
    TempDir d("zarr-fill");
    std::vector<double> values = oracle_values();
    for (std::int64_t k = 0; k < 4; ++k)  // the first chunk row (cz = 4) all fill
        for (std::int64_t i = 0; i < NX * NY; ++i) values[static_cast<std::size_t>(k * NX * NY + i)] = 42;
    for (const char* c : {"none", "zstd"}) {
        ZarrWriteOptions o;
        o.chunks = {4, 6, 7};
        o.compressor = c;
        o.fill = "42";
        o.fill_value = 42;
        o.drop_fill_chunks = true;
        const auto dir = d.path / (std::string(c) + ".zarr");
        write_zarr(dir, values, NX, NY, NZ, o);
        CHECK(!std::filesystem::exists(dir / "0.0.0"));
        CHECK(std::filesystem::exists(dir / "1.0.0"));
        CHECK(samples_of(read_volume(dir.string())) == values);
        // by chunk rows, the missing row among them, into a buffer that is not zeroed
        ZarrChunkRows rows(open_zarr(dir.string()));
        std::vector<std::byte> got(static_cast<std::size_t>(NX * NY * NZ), std::byte{0xee});
        for (std::int64_t r = 0; r < 3; ++r) rows.read_row(r, got.data() + r * 4 * NX * NY);
        std::vector<double> s;
        for (std::byte b : got) s.push_back(static_cast<double>(std::to_integer<int>(b)));
        CHECK(s == values);
    }
    ZarrWriteOptions f;
    f.dtype = "<f4";
    f.chunks = {4, 6, 7};
    f.fill = "\"NaN\"";
    f.fill_value = 1e300;  // none dropped by value: drop the first row by hand below
    write_zarr(d.path / "nan.zarr", oracle_values(), NX, NY, NZ, f);
    std::filesystem::remove(d.path / "nan.zarr" / "0.0.0");
    const Volume v = read_volume((d.path / "nan.zarr").string());
    const std::vector<double> s = samples_of(v);
    CHECK(std::isnan(s[0]));
    CHECK(std::isnan(s[static_cast<std::size_t>(3 * NX * NY + 5 * NX + 6)]));  // the last sample of chunk (0,0,0)
    CHECK(s[7] == 7);                                                            // chunk (0,0,1) is there
    CHECK(s[static_cast<std::size_t>(4 * NX * NY)] == 80);
}

TEST_CASE("zarr: OME-Zarr reads level 0 with its scale and translation, plain stores take --spacing", "[formats][zarr]") {
    TempDir d("zarr-ome");
    ZarrWriteOptions o;
    o.leading = {1, 1};  // (t, c, z, y, x)
    o.chunks = {4, 4, 4};
    o.compressor = "blosc";
    write_ome_zarr(d.path / "img.ome.zarr", oracle_values(), NX, NY, NZ, {2.5, 0.5, 0.25}, {10, 20, 30}, o);
    const Volume v = read_volume((d.path / "img.ome.zarr").string());
    CHECK(v.grid.dims == std::array<std::int64_t, 3>{NX, NY, NZ});
    CHECK(v.grid.spacing == std::array<double, 3>{0.25, 0.5, 2.5});
    CHECK(v.grid.origin == std::array<double, 3>{30, 20, 10});
    CHECK(samples_of(v) == oracle_values());
    const VolumeInfo i = probe_volume((d.path / "img.ome.zarr").string());
    CHECK(i.format == "ome-zarr");
    CHECK_THAT(i.encoding, Contains("level 0 \"0\"") && Contains("shape (1, 1, 9, 11, 13)") && Contains("blosc lz4"));
    // a plain store: --spacing as for raw files; info says shape, dtype, chunks, compressor
    write_zarr(d.path / "p.zarr", oracle_values(), NX, NY, NZ, {});
    RawOptions raw;
    raw.spacing = std::array<double, 3>{1, 2, 3};
    CHECK(read_volume((d.path / "p.zarr").string(), raw).grid.spacing == std::array<double, 3>{1, 2, 3});
    const VolumeInfo p = prove_volume((d.path / "p.zarr").string());
    CHECK(p.format == "zarr");
    CHECK_THAT(p.encoding, Contains("shape (9, 11, 13) order C") && Contains("dtype |u1") && Contains("chunks (8, 8, 8)") &&
                               Contains("compressor none"));
    CHECK(looks_like_volume((d.path / "p.zarr").string()));
    CHECK(looks_like_volume((d.path / "img.ome.zarr").string()));
}

TEST_CASE("zarr: an OME-Zarr image's other resolution levels by RawOptions::resolution_level, refused beyond them and elsewhere", "[formats][zarr]") {
    TempDir d("zarr-levels");
    ZarrWriteOptions o;
    o.leading = {1};  // (c, z, y, x)
    o.chunks = {4, 4, 4};
    write_ome_zarr(d.path / "img.ome.zarr", oracle_values(), NX, NY, NZ, {2.5, 0.5, 0.25}, {10, 20, 30}, o);
    const std::string img = (d.path / "img.ome.zarr").string();
    RawOptions raw;
    raw.resolution_level = 1;  // the writer's level 1: half the samples, constant 3, scale 2
    const Volume v = read_volume(img, raw);
    CHECK(v.grid.dims == std::array<std::int64_t, 3>{(NX + 1) / 2, (NY + 1) / 2, (NZ + 1) / 2});
    CHECK(v.grid.spacing == std::array<double, 3>{2, 2, 2});
    CHECK(v.grid.origin == std::array<double, 3>{0, 0, 0});
    for (double x : samples_of(v)) CHECK(x == 3);
    CHECK_THAT(probe_volume(img, raw).encoding, Contains("level 1 \"1\" of 2"));
    CHECK_THAT(probe_volume(img).encoding, Contains("level 0 \"0\" of 2"));
    raw.resolution_level = 2;
    CHECK_THROWS_WITH(read_volume(img, raw), Contains("resolution level 2 asked, the image has 2 (0..1, 0 the full resolution)"));
    write_zarr(d.path / "p.zarr", oracle_values(), NX, NY, NZ, {});
    raw.resolution_level = 1;
    CHECK_THROWS_WITH(read_volume((d.path / "p.zarr").string(), raw), Contains("a Zarr array has one resolution"));
    CHECK_THROWS_AS(read_volume((d.path / "p.zarr").string(), raw), InvalidArgument);
    const std::string nrrd = (d.path / "v.nrrd").string();
    {
        std::ofstream f(nrrd, std::ios::binary);
        f << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" << std::string(8, '\0');
    }
    CHECK_THROWS_WITH(read_volume(nrrd, raw), Contains("a nrrd volume has one resolution: --resolution-level applies to OME-Zarr images"));
}

TEST_CASE("zarr: must-fail stores, one per defect class", "[formats][zarr]") {
    TempDir d("zarr-bad");
    const std::string good_chunk(32, '\x01');
    auto err = [&](const std::string& name, const std::string& za, const std::string& chunk = "") {
        const std::string dir = store(d, name, za, chunk);
        return error_of([&] { (void)read_volume(dir); });
    };
    const std::string s3 = "[2, 4, 4]";
    CHECK(err("ok", zarray(s3, s3), good_chunk) == "(nothing thrown)");
    CHECK_THAT(err("json", "{\"zarr_format\": 2, \"shape\": [2, 4, 4],"), Contains("json/.zarray: bad JSON"));
    CHECK_THAT(err("dtype", zarray(s3, s3, "<f2")), Contains("dtype/.zarray: dtype \"<f2\" is not read"));
    CHECK_THAT(err("complex", zarray(s3, s3, "<c8")), Contains("dtype \"<c8\" is not read"));
    CHECK_THAT(err("order", zarray(s3, s3, "|u2")), Contains("dtype \"|u2\" gives no byte order"));
    CHECK_THAT(err("escaped", zarray(s3, s3, "\\u001b[2J")), Contains("dtype \"\\x1b[2J\" is not read"));
    CHECK_THAT(err("v3", "{\"zarr_format\": 3, \"shape\": [2, 4, 4]}"), Contains("v3/.zarray: zarr_format 3 is not read (Zarr v2"));
    CHECK_THAT(err("twod", zarray("[4, 4]", "[4, 4]")), Contains("twod/.zarray: shape (4, 4) is not a volume"));
    CHECK_THAT(err("fourd", zarray("[2, 2, 4, 4]", "[1, 2, 4, 4]")), Contains("shape (2, 2, 4, 4) is not a volume"));
    CHECK_THAT(err("negative", zarray("[2, -4, 4]", s3)), Contains("negative/.zarray: \"shape\"[1] -4 is not an integer in 0.."));
    CHECK_THAT(err("fraction", zarray("[2, 4.5, 4]", s3)), Contains("\"shape\"[1] 4.5 is not an integer"));
    CHECK_THAT(err("overflow", zarray("[4294967296, 4294967296, 4294967296]", s3)), Contains("overflow/.zarray: shape (4294967296, 4294967296, 4294967296)") && Contains("size overflow"));
    CHECK_THAT(err("manychunks", zarray("[65536, 65536, 65536]", "[1, 1, 2]")), Contains("makes 140737488355328 chunks, more than a store holds"));
    CHECK_THAT(err("empty", zarray("[2, 0, 4]", s3)), Contains("shape (2, 0, 4) has an empty axis"));
    CHECK_THAT(err("chunkcount", zarray(s3, "[2, 4]")), Contains("chunks (2, 4) do not have one entry per axis"));
    CHECK_THAT(err("hugechunk", zarray("[2048, 2048, 2048]", "[2048, 2048, 1024]")), Contains("more than the 2 GiB a chunk may hold"));
    CHECK_THAT(err("zerochunk", zarray(s3, "[2, 0, 4]")), Contains("\"chunks\"[1] 0 is not an integer in 1.."));
    auto with = [&](std::string za, const std::string& from, const std::string& to) { return za.replace(za.find(from), from.size(), to); };
    CHECK_THAT(err("filters", with(zarray(s3, s3), "\"filters\": null", "\"filters\": [{\"id\": \"delta\", \"dtype\": \"|u1\"}]")),
               Contains("filters/.zarray: filters [\"delta\"] are not supported"));
    CHECK_THAT(err("lz4", zarray(s3, s3, "|u1", "{\"id\": \"lz4\"}")), Contains("compressor \"lz4\" is not read"));
    CHECK_THAT(err("fill", with(zarray(s3, s3), "\"fill_value\": 0", "\"fill_value\": 300")), Contains("fill_value 300 is not a uint8 value"));
    // chunks: the file is named, and what is wrong with it
    CHECK_THAT(err("short", zarray(s3, s3), std::string(31, '\x01')), Contains("short/0.0.0: uncompressed chunk of 31 bytes, expected 32"));
    CHECK_THAT(err("long", zarray(s3, s3), std::string(33, '\x01')), Contains("long/0.0.0: uncompressed chunk of 33 bytes, expected 32"));
    const std::string zlib = "{\"id\": \"zlib\", \"level\": 1}";
    CHECK_THAT(err("zsmall", zarray(s3, s3, "|u1", zlib), zarr_compress(std::string(30, '\x01'), "zlib", 1)),
               Contains("zsmall/0.0.0: compressed data ends after 30 decompressed bytes, expected 32"));
    CHECK_THAT(err("zbig", zarray(s3, s3, "|u1", zlib), zarr_compress(std::string(40, '\x01'), "zlib", 1)),
               Contains("zbig/0.0.0: compressed data decompresses to more than 32 bytes"));
    const std::string zstd = "{\"id\": \"zstd\", \"level\": 1}";
    CHECK_THAT(err("zstdsize", zarray(s3, s3, "|u1", zstd), zarr_compress(std::string(40, '\x01'), "zstd", 1)),
               Contains("zstdsize/0.0.0: zstd frame declares 40 bytes, a chunk holds 32"));
    std::string cut = zarr_compress(std::string(32, '\x01') + std::string(4000, '\x02'), "zstd", 1);
    CHECK_THAT(err("truncated", zarray("[2, 4, 504]", "[2, 4, 504]", "|u1", zstd), cut.substr(0, cut.size() - 3)),
               Contains("truncated/0.0.0: corrupt or truncated zstd chunk"));
    const std::string blosc = "{\"id\": \"blosc\", \"cname\": \"lz4\", \"clevel\": 5, \"shuffle\": 1}";
    std::string bcut = zarr_compress(std::string(32, '\x03'), "blosc", 1);
    CHECK_THAT(err("bloscbad", zarray(s3, s3, "|u1", blosc), bcut.substr(0, 10)), Contains("bloscbad/0.0.0: not a valid blosc chunk"));
    CHECK_THAT(err("bloscsize", zarray(s3, s3, "|u1", blosc), zarr_compress(std::string(64, '\x03'), "blosc", 1)),
               Contains("bloscsize/0.0.0: blosc chunk declares 64 bytes, a chunk holds 32"));
    // a bomb: 64 MiB of zeros in 64 KiB claims a 32-byte chunk; refused at its size, not inflated
    CHECK_THAT(err("bomb", zarray(s3, s3, "|u1", zlib), zarr_compress(std::string(std::size_t{64} << 20, '\0'), "zlib", 1)),
               Contains("bomb/0.0.0: chunk file of") && Contains("is larger than a chunk of 32 bytes compresses to"));
    CHECK_THAT(err("bomb2", zarray("[64, 1024, 1024]", "[64, 1024, 1024]", "|u1", zlib), zarr_compress(std::string(1000, '\0'), "zlib", 1)),
               Contains("bomb2/0.0.0: a") && Contains("zlib chunk cannot hold 67108864 bytes (deflate expands at most 1032:1)"));
    // chunks decoded in parallel: the first bad one in key order is reported, whatever the schedule
    {
        const std::string dir = store(d, "two", zarray("[2, 4, 64]", "[2, 4, 4]"), std::string(5, '\x01'));
        for (int c = 1; c < 16; ++c) zarr_put(std::filesystem::path(dir) / ("0.0." + std::to_string(c)), std::string(c == 9 ? 7 : 32, '\x01'));
        for (int k = 0; k < 20; ++k)
            CHECK_THAT(error_of([&] { (void)read_volume(dir); }), Contains("two/0.0.0: uncompressed chunk of 5 bytes"));
    }
    // OME-Zarr: the dataset path stays inside the image folder
    zarr_put(d.path / "up.zarr" / ".zattrs", R"({"multiscales": [{"datasets": [{"path": "../ok"}]}]})");
    CHECK_THAT(error_of([&] { (void)read_volume((d.path / "up.zarr").string()); }),
               Contains("up.zarr/.zattrs: dataset path \"../ok\" is not a relative path of plain names"));
    zarr_put(d.path / "abs.zarr" / ".zattrs", R"({"multiscales": [{"datasets": [{"path": "/etc"}]}]})");
    CHECK_THAT(error_of([&] { (void)read_volume((d.path / "abs.zarr").string()); }), Contains("dataset path \"/etc\" is not a relative path"));
    std::filesystem::create_directories(d.path / "nothing.zarr");
    CHECK_THAT(error_of<IoError>([&] { (void)read_volume((d.path / "nothing.zarr").string()); }),
               Contains("nothing.zarr: not a Zarr store (no .zarray"));
    zarr_put(d.path / "three.zarr" / "zarr.json", "{}");
    CHECK_THAT(error_of([&] { (void)read_volume((d.path / "three.zarr").string()); }), Contains("a Zarr v3 store is not read"));
}
