// Mapped volumes (formats/mapped_file.hpp, map_volume) against read_volume: the same grid, type and
// bytes for raw and NRRD files (attached, detached, with offsets that are not page-aligned), the
// fallback for payloads that need decoding (gzip, big endian, widening types), copy-on-write
// writes that never reach the file, and range errors. Also CRC-32 (formats/crc32.hpp) against zlib.
#include <catch2/catch.hpp>

#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "format_test_util.hpp"
#include "formats/crc32.hpp"
#include "formats/mapped_file.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"

using namespace meshless;
namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("meshless-mapped-" + std::to_string(::getpid()) + "-" + std::to_string(std::rand()));
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

void write_bytes(const fs::path& p, const std::string& head, const std::vector<std::byte>& body) {
    std::ofstream f(p, std::ios::binary);
    f.write(head.data(), static_cast<std::streamsize>(head.size()));
    f.write(reinterpret_cast<const char*>(body.data()), static_cast<std::streamsize>(body.size()));
}

void check_same(const Volume& a, const Volume& b) {
    CHECK(a.grid == b.grid);
    CHECK(a.type == b.type);
    CHECK(a.bytes == b.bytes);
}

}  // namespace

TEST_CASE("map_volume gives read_volume's volume for raw and NRRD files", "[formats][mapped]") {
    TempDir d;
    const std::array<std::int64_t, 3> dims{13, 11, 7};
    for (StoredType t : {StoredType::u8, StoredType::i16, StoredType::u16, StoredType::f32}) {
        INFO(to_string(t));
        const auto body = test::field_bytes(t, dims, false);
        const fs::path raw = d.path / (std::string("v_13x11x7_") + to_string(t) + ".raw");
        write_bytes(raw, "", body);
        const Volume m = map_volume(raw.string());
        check_same(m, read_volume(raw.string()));
        CHECK(m.bytes.adopted());
        // attached NRRD: the header length (not a multiple of the page size) is the data offset
        const std::string head = std::string("NRRD0004\ntype: ") + (t == StoredType::u8 ? "uint8" : t == StoredType::i16 ? "int16" : t == StoredType::u16 ? "uint16" : "float") +
                                 "\ndimension: 3\nsizes: 13 11 7\nspacings: 0.5 0.5 2\nendian: little\nencoding: raw\n\n";
        const fs::path nrrd = d.path / (std::string("v_") + to_string(t) + ".nrrd");
        write_bytes(nrrd, head, body);
        const Volume mn = map_volume(nrrd.string());
        check_same(mn, read_volume(nrrd.string()));
        CHECK(mn.bytes.adopted());
    }
}

TEST_CASE("map_volume falls back to reading when the payload needs decoding", "[formats][mapped]") {
    TempDir d;
    const std::array<std::int64_t, 3> dims{9, 8, 5};
    // big-endian int16 (swapped), int8 (widened to int16), gzip
    const auto be = test::field_bytes(StoredType::i16, dims, true);
    write_bytes(d.path / "be.nrrd", "NRRD0004\ntype: short\ndimension: 3\nsizes: 9 8 5\nendian: big\nencoding: raw\n\n", be);
    const Volume a = map_volume((d.path / "be.nrrd").string());
    check_same(a, read_volume((d.path / "be.nrrd").string()));
    CHECK(!a.bytes.adopted());
    const auto i8 = test::field_bytes(StoredType::i8, dims, false);
    write_bytes(d.path / "s8.nrrd", "NRRD0004\ntype: int8\ndimension: 3\nsizes: 9 8 5\nencoding: raw\n\n", i8);
    const Volume b = map_volume((d.path / "s8.nrrd").string());
    check_same(b, read_volume((d.path / "s8.nrrd").string()));
    CHECK(b.type == SampleType::i16);
    CHECK(!b.bytes.adopted());
}

TEST_CASE("a mapped volume is copy-on-write: writes never reach the file", "[formats][mapped]") {
    TempDir d;
    const auto body = test::field_bytes(StoredType::u8, {16, 16, 16}, false);
    const fs::path raw = d.path / "w_16x16x16_uint8.raw";
    write_bytes(raw, "", body);
    Volume m = map_volume(raw.string());
    REQUIRE(m.bytes.adopted());
    m.bytes[100] = std::byte{0xAB};
    CHECK(m.bytes[100] == std::byte{0xAB});
    const Volume again = read_volume(raw.string());
    CHECK(again.bytes[100] == body[100]);
    Volume copy = m;  // a copy owns its bytes and keeps the write
    CHECK(!copy.bytes.adopted());
    CHECK(copy.bytes == m.bytes);
}

TEST_CASE("map_file_range checks the range against the file", "[formats][mapped]") {
    TempDir d;
    write_bytes(d.path / "f.bin", "0123456789", {});
    const SampleBytes b = map_file_range((d.path / "f.bin").string(), 3, 4);
    REQUIRE(b.size() == 4);
    CHECK(std::memcmp(b.data(), "3456", 4) == 0);
    CHECK(map_file_range((d.path / "f.bin").string(), 10, 0).empty());
    CHECK_THROWS_AS(map_file_range((d.path / "f.bin").string(), 7, 4), FormatError);
    CHECK_THROWS_AS(map_file_range((d.path / "f.bin").string(), 11, 0), FormatError);
    CHECK_THROWS_AS(map_file_range((d.path / "missing.bin").string(), 0, 1), IoError);
    CHECK_THROWS_AS(map_file_range(d.path.string(), 0, 1), IoError);  // a directory
    // a raw file of the wrong size is still diagnosed by the reader, mapped or not
    write_bytes(d.path / "short_4x4x4_uint8.raw", "", std::vector<std::byte>(63));
    CHECK_THROWS_AS(map_volume((d.path / "short_4x4x4_uint8.raw").string()), FormatError);
}

TEST_CASE("crc32_ieee equals zlib's crc32 for any length, alignment and start value", "[formats][crc32]") {
    std::mt19937 rng(7);
    std::vector<unsigned char> buf(70000);
    for (auto& c : buf) c = static_cast<unsigned char>(rng());
    for (std::size_t n : {0u, 1u, 15u, 16u, 17u, 63u, 64u, 65u, 79u, 80u, 128u, 1000u, 4097u, 65536u})
        for (std::size_t off : {0u, 1u, 3u, 8u})
            for (std::uint32_t start : {0u, 0xdeadbeefu}) {
                const auto z = static_cast<std::uint32_t>(crc32(start, buf.data() + off, static_cast<uInt>(n)));
                INFO("n " << n << " off " << off);
                CHECK(crc32_ieee(start, buf.data() + off, n) == z);
            }
    // continuation: two pieces give the whole
    const std::uint32_t whole = crc32_ieee(0, buf.data(), 50000);
    CHECK(crc32_ieee(crc32_ieee(0, buf.data(), 12345), buf.data() + 12345, 50000 - 12345) == whole);
}
