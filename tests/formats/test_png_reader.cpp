// PNG reader (formats/png_reader.hpp): what libpng decodes comes back as RGB; must-fail inputs per
// defect class (signature, truncation, damaged chunk CRC, sizes out of 1..16384, a header claiming
// more pixels than the bytes can hold), all FormatError naming the file.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "formats/crc32.hpp"
#include "formats/png_reader.hpp"
#include "formats/png_writer.hpp"
#include "kernels/errors.hpp"
#include "tests/error_of.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
using Catch::Matchers::Contains;

namespace {

std::vector<unsigned char> file_bytes(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put_be32(std::vector<unsigned char>& b, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + i] = static_cast<unsigned char>(v >> (24 - 8 * i));
}

/// Rewrites the IHDR width and height (bytes 16..23) and fixes its CRC, so only the sizes are wrong.
std::vector<unsigned char> with_size(std::vector<unsigned char> b, std::uint32_t w, std::uint32_t h) {
    put_be32(b, 16, w);
    put_be32(b, 20, h);
    put_be32(b, 29, crc32_ieee(0, b.data() + 12, 17));  // CRC over "IHDR" + 13 data bytes
    return b;
}

}  // namespace

TEST_CASE("PNG reader decodes what the writer wrote, from a file and from memory", "[render]") {
    test::TempDir d("pngr");
    Image img;
    img.width = 5;
    img.height = 3;
    for (int i = 0; i < 45; ++i) img.rgb.push_back(static_cast<std::uint8_t>(i * 5));
    const auto p = (d / "a.png").string();
    write_png(img, p);
    CHECK(read_png(p).rgb == img.rgb);
    const auto bytes = file_bytes(p);
    const Image m = decode_png(bytes, "mem");
    CHECK(m.width == 5);
    CHECK(m.height == 3);
    CHECK(m.rgb == img.rgb);
}

TEST_CASE("PNG reader refuses damaged files, each defect with FormatError naming the file", "[render]") {
    test::TempDir d("pngr");
    Image img;
    img.width = img.height = 16;
    img.rgb.assign(3 * 256, 90);
    const auto p = (d / "good.png").string();
    write_png(img, p);
    const auto good = file_bytes(p);
    REQUIRE(std::memcmp(good.data() + 12, "IHDR", 4) == 0);

    CHECK_THAT(test::error_of([&] { decode_png(std::vector<unsigned char>{'G', 'I', 'F', '8', '9', 'a', 0, 0}, "x.png"); }),
               Contains("x.png") && Contains("signature"));
    CHECK_THAT(test::error_of([&] { decode_png(std::vector<unsigned char>{}, "empty.png"); }), Contains("empty.png"));
    // truncated: header only, then half of the data
    for (std::size_t keep : {std::size_t{20}, std::size_t{40}, good.size() / 2, good.size() - 13}) {
        const std::vector<unsigned char> t(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(keep));
        CHECK_THAT(test::error_of([&] { decode_png(t, "cut.png"); }), Contains("cut.png"));
    }
    // a damaged IHDR (CRC no longer matches)
    auto bad_crc = good;
    bad_crc[17] ^= 0x40;
    CHECK_THAT(test::error_of([&] { decode_png(bad_crc, "crc.png"); }), Contains("crc.png"));
    // sizes outside 1..16384 with a valid CRC
    CHECK_THAT(test::error_of([&] { decode_png(with_size(good, 16385, 1), "wide.png"); }), Contains("wide.png") && Contains("16384"));
    CHECK_THAT(test::error_of([&] { decode_png(with_size(good, 1, 16385), "tall.png"); }), Contains("16384"));
    CHECK_THAT(test::error_of([&] { decode_png(with_size(good, 0, 16), "zero.png"); }), Contains("zero.png"));
    // a header claiming 16000 x 16000 pixels from ~100 bytes: refused before allocating 768 MB
    CHECK_THAT(test::error_of([&] { decode_png(with_size(good, 16000, 16000), "claim.png"); }),
               Contains("claim.png") && Contains("more than its"));
    // a plausible size that the data does not fill: libpng reports the missing rows
    CHECK_THAT(test::error_of([&] { decode_png(with_size(good, 16, 200), "short.png"); }), Contains("short.png"));
    CHECK_THROWS_AS(read_png((d / "absent.png").string()), IoError);
    CHECK_THROWS_AS(read_png(d.path.string()), IoError);
}
