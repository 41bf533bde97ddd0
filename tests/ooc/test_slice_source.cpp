// Slice sources (streamed raw / NRRD / gzip payloads, upsampling) and conversions of real volumes
// compared with read_volume.
#include <catch2/catch.hpp>
#include <zlib.h>

#include <cstring>
#include <filesystem>

#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "ooc_test_util.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

// Reads the whole source in slabs of `slab` slices (the converter's access pattern).
Volume drain(SliceSource& s, std::int64_t slab) {
    Volume v(s.grid(), s.type());
    const std::size_t slice = static_cast<std::size_t>(s.grid().dims[0] * s.grid().dims[1]) * sample_size(s.type());
    for (std::int64_t k = 0; k < s.grid().dims[2]; k += slab) {
        const std::int64_t n = std::min(slab, s.grid().dims[2] - k);
        s.read_slices(k, n, v.bytes.data() + static_cast<std::size_t>(k) * slice);
    }
    return v;
}

void swap_bytes(std::string& b, std::size_t elem) {
    for (std::size_t i = 0; i + elem <= b.size(); i += elem) std::reverse(b.begin() + i, b.begin() + i + elem);
}

}  // namespace

TEST_CASE("streamed raw and NRRD payloads equal read_volume", "[ooc]") {
    TempDir dir("ooc-slices");
    const Volume v = random_volume({23, 11, 17}, SampleType::u16);
    const std::string raw(reinterpret_cast<const char*>(v.bytes.data()), v.bytes.size());

    SECTION("raw, little and big endian") {
        for (bool big : {false, true}) {
            std::string b = raw;
            if (big) swap_bytes(b, 2);
            const auto path = (dir / "vol.raw").string();
            write_bytes(path, b);
            RawOptions o;
            o.dims = v.grid.dims;
            o.type = SampleType::u16;
            o.big_endian = big;
            auto src = open_slice_source(path, o);
            CHECK(src->type() == SampleType::u16);
            CHECK(drain(*src, 5).bytes == v.bytes);
            CHECK(drain(*src, 1).bytes == read_volume(path, o).bytes);
        }
    }
    SECTION("NRRD with a byte skip and a header") {
        write_bytes(dir / "d.raw", std::string(13, 'x') + raw);
        write_bytes(dir / "v.nhdr", "NRRD0004\ntype: ushort\ndimension: 3\nsizes: 23 11 17\nencoding: raw\nendian: little\n"
                                    "byte skip: 13\ndata file: d.raw\n");
        auto src = open_slice_source((dir / "v.nhdr").string());
        CHECK(drain(*src, 4).bytes == v.bytes);
    }
    SECTION("NRRD gzip payload, big endian, read in slabs and going back") {
        std::string b = raw;
        swap_bytes(b, 2);
        uLongf n = compressBound(static_cast<uLong>(b.size()));
        std::string z(n, '\0');
        REQUIRE(compress2(reinterpret_cast<Bytef*>(z.data()), &n, reinterpret_cast<const Bytef*>(b.data()),
                          static_cast<uLong>(b.size()), 6) == Z_OK);
        z.resize(n);
        write_bytes(dir / "d.raw.gz", z);
        write_bytes(dir / "v.nhdr", "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 23 11 17\nencoding: gzip\nendian: big\n"
                                    "data file: d.raw.gz\n");
        auto src = open_slice_source((dir / "v.nhdr").string());
        CHECK(drain(*src, 3).bytes == v.bytes);
        CHECK(drain(*src, 7).bytes == v.bytes);  // starts again from slice 0
    }
    SECTION("a gzip payload longer than the header says is a format error, streamed as when read whole") {
        std::string b = raw + "xy";
        uLongf n = compressBound(static_cast<uLong>(b.size()));
        std::string z(n, '\0');
        REQUIRE(compress2(reinterpret_cast<Bytef*>(z.data()), &n, reinterpret_cast<const Bytef*>(b.data()),
                          static_cast<uLong>(b.size()), 6) == Z_OK);
        z.resize(n);
        write_bytes(dir / "long.raw.gz", z);
        write_bytes(dir / "long.nhdr", "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 23 11 17\nencoding: gzip\n"
                                       "data file: long.raw.gz\n");
        const std::string path = (dir / "long.nhdr").string();
        const std::string want = "long.raw.gz: compressed data decompresses to more than " + std::to_string(raw.size()) + " bytes";
        CHECK_THROWS_WITH(read_volume(path), Catch::Contains(want));
        auto src = open_slice_source(path);
        CHECK_THROWS_WITH(drain(*src, 5), Catch::Contains(want));
    }
    SECTION("a raw file that is too short is a format error") {
        write_bytes(dir / "short.raw", raw.substr(0, raw.size() - 2));
        RawOptions o;
        o.dims = v.grid.dims;
        o.type = SampleType::u16;
        CHECK_THROWS_AS(open_slice_source((dir / "short.raw").string(), o), FormatError);
    }
}

TEST_CASE("trilinear upsampling keeps the original voxels and reproduces linear fields", "[ooc]") {
    SECTION("original voxels at multiples of f, every type, both methods") {
        for (SampleType t : {SampleType::u8, SampleType::i16, SampleType::u16, SampleType::f32})
            for (Upsampling m : {Upsampling::trilinear, Upsampling::tricubic})
                for (int f : {1, 2, 3}) {
                    const Volume v = random_volume({7, 5, 4}, t);
                    auto src = make_upsampling_source(v, f, m, "mem");
                    const GridSpec& g = src->grid();
                    for (int a = 0; a < 3; ++a) {
                        CHECK(g.dims[a] == (v.grid.dims[a] - 1) * f + 1);
                        CHECK(g.spacing[a] == v.grid.spacing[a] / f);
                        CHECK(g.origin[a] == v.grid.origin[a]);
                    }
                    const Volume up = drain(*src, 3);
                    const std::size_t ss = sample_size(t);
                    for (std::int64_t k = 0; k < v.grid.dims[2]; ++k)
                        for (std::int64_t j = 0; j < v.grid.dims[1]; ++j)
                            for (std::int64_t i = 0; i < v.grid.dims[0]; ++i)
                                REQUIRE(std::memcmp(up.bytes.data() + g.index(i * f, j * f, k * f) * ss,
                                                    v.bytes.data() + v.grid.index(i, j, k) * ss, ss) == 0);
                }
    }
    SECTION("linear fields are exact (dyadic coefficients, f = 4)") {
        GridSpec g;
        g.dims = {6, 5, 4};
        Volume v(g, SampleType::f32);
        auto lin = [](double x, double y, double z) { return 3 * x - 5 * y + 2 * z + 7; };
        for (std::int64_t k = 0; k < 4; ++k)
            for (std::int64_t j = 0; j < 5; ++j)
                for (std::int64_t i = 0; i < 6; ++i)
                    reinterpret_cast<float*>(v.bytes.data())[g.index(i, j, k)] = static_cast<float>(lin(i, j, k));
        auto src = make_upsampling_source(v, 4, Upsampling::trilinear, "mem");
        const Volume up = drain(*src, 2);
        const GridSpec& G = up.grid;
        for (std::int64_t k = 0; k < G.dims[2]; ++k)
            for (std::int64_t j = 0; j < G.dims[1]; ++j)
                for (std::int64_t i = 0; i < G.dims[0]; ++i)
                    REQUIRE(reinterpret_cast<const float*>(up.bytes.data())[G.index(i, j, k)] ==
                            static_cast<float>(lin(i / 4.0, j / 4.0, k / 4.0)));
        // Catmull-Rom also reproduces linear fields away from the clamped borders.
        auto cub = make_upsampling_source(v, 4, Upsampling::tricubic, "mem");
        const Volume uc = drain(*cub, 5);
        for (std::int64_t k = 4; k < 8; ++k)
            for (std::int64_t j = 4; j < 12; ++j)
                for (std::int64_t i = 4; i < 16; ++i)
                    REQUIRE(reinterpret_cast<const float*>(uc.bytes.data())[G.index(i, j, k)] ==
                            Approx(lin(i / 4.0, j / 4.0, k / 4.0)).margin(1e-5));
    }
    SECTION("integer samples are rounded and clamped to the type") {
        GridSpec g;
        g.dims = {4, 1, 1};
        Volume v(g, SampleType::u8);
        const std::uint8_t vals[] = {0, 255, 255, 0};
        std::memcpy(v.bytes.data(), vals, 4);
        auto src = make_upsampling_source(v, 4, Upsampling::tricubic, "mem");  // overshoots above 255
        const Volume up = drain(*src, 1);
        const auto* p = reinterpret_cast<const std::uint8_t*>(up.bytes.data());
        CHECK(p[6] == 255);  // between the two 255s, Catmull-Rom gives > 255
        auto lin = make_upsampling_source(v, 2, Upsampling::trilinear, "mem");
        const Volume ul = drain(*lin, 1);
        CHECK(reinterpret_cast<const std::uint8_t*>(ul.bytes.data())[1] == 128);  // 127.5 rounds up
    }
    SECTION("bad factor") {
        const Volume v = random_volume({3, 3, 3}, SampleType::u8);
        CHECK_THROWS_AS(make_upsampling_source(v, 0, Upsampling::trilinear, "mem"), InvalidArgument);
    }
}

TEST_CASE("an upsampled volume streams into a brick store equal to the upsampled slices", "[ooc]") {
    TempDir dir("ooc-synth");
    const Volume v = random_volume({9, 7, 6}, SampleType::i16);
    auto src = make_upsampling_source(v, 3, Upsampling::tricubic, "mem");
    const Volume up = drain(*src, 4);
    auto src2 = make_upsampling_source(v, 3, Upsampling::tricubic, "mem");
    ConvertParams p;
    p.brick_edge = 8;
    const std::string path = (dir / "s.mlb").string();
    convert_to_brick_store(*src2, path, p);
    const auto store = BrickStore::open(path);
    CHECK(reassemble(*store).bytes == up.bytes);
}

TEST_CASE("real volumes convert to brick stores that reassemble to read_volume", "[ooc]") {
    if (!have_shared_data()) {
        WARN("shared data not found; skipped");
        return;
    }
    TempDir dir("ooc-real");
    const fs::path d = shared_data();
    for (const fs::path& p : {d / "vtkjs_LIDC2" / "LIDC2.vti", d / "vtk_headsq" / "quarter.nhdr",
                             d / "tooth" / "tooth_103x94x161_uint8.raw"}) {
        INFO(p.string());
        const Volume ref = read_volume(p.string());
        for (std::uint32_t B : {16u, 32u}) {
            auto src = open_slice_source(p.string());
            CHECK(src->grid() == ref.grid);
            CHECK(src->type() == ref.type);
            ConvertParams cp;
            cp.brick_edge = B;
            cp.threads = 2;
            const std::string out = (dir / "r.mlb").string();
            const ConvertStats st = convert_to_brick_store(*src, out, cp);
            CHECK(st.output_bytes < st.input_bytes);  // these CT volumes compress
            const auto store = BrickStore::open(out);
            const Volume back = reassemble(*store);
            CHECK(back.grid == ref.grid);
            CHECK(back.bytes == ref.bytes);
            const auto r = ref.value_range();
            CHECK(store->info().value_min == r[0]);
            CHECK(store->info().value_max == r[1]);
        }
    }
}
