// PNG writer/reader: round trip of pixels, atomic failure on an unwritable path, rejection of
// non-PNG input.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <zlib.h>

#include "formats/png_writer.hpp"
#include "kernels/errors.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;

namespace {
/// The chunk types of a PNG file in order, each chunk's CRC checked with zlib's crc32 (an
/// implementation other than the writer's; libpng forgives some CRC errors on reading).
std::vector<std::string> checked_chunks(const std::string& path, std::size_t max_idat) {
    std::ifstream in(path, std::ios::binary);
    const std::string d((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(d.size() >= 8);
    CHECK(d.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    auto u32 = [&](std::size_t at) {
        return std::uint32_t(std::uint8_t(d[at])) << 24 | std::uint32_t(std::uint8_t(d[at + 1])) << 16 |
               std::uint32_t(std::uint8_t(d[at + 2])) << 8 | std::uint32_t(std::uint8_t(d[at + 3]));
    };
    std::vector<std::string> types;
    for (std::size_t at = 8; at < d.size();) {
        REQUIRE(at + 12 <= d.size());
        const std::uint32_t n = u32(at);
        REQUIRE(at + 12 + n <= d.size());
        const std::string type = d.substr(at + 4, 4);
        INFO("chunk " << type << " of " << n << " bytes");
        CHECK(u32(at + 8 + n) == ::crc32(0, reinterpret_cast<const Bytef*>(d.data() + at + 4), 4 + n));
        if (type == "IDAT") CHECK(n <= max_idat);
        types.push_back(type);
        at += 12 + n;
    }
    return types;
}
}  // namespace

TEST_CASE("PNG round trip reproduces the pixels", "[splat]") {
    test::TempDir dir("png");
    std::mt19937 rng(7);
    // random bytes do not compress: the largest encodings (the writer sizes its buffer for the worst case)
    for (auto [w, h] : {std::pair{37, 23}, std::pair{1, 1}, std::pair{256, 3}, std::pair{1000, 700}}) {
        Image img;
        img.width = w;
        img.height = h;
        img.rgb.resize(3 * w * h);
        for (auto& b : img.rgb) b = static_cast<std::uint8_t>(rng());
        const std::string path = (dir / "img.png").string();
        write_png(img, path);
        const Image back = read_png(path);
        CHECK(back.width == w);
        CHECK(back.height == h);
        CHECK(back.rgb == img.rgb);
        const auto types = checked_chunks(path, std::size_t{1} << 20);
        REQUIRE(types.size() >= 3);
        CHECK(types.front() == "IHDR");
        CHECK(types.back() == "IEND");
        if (w == 1000) CHECK(types.size() > 4);  // 2.1 MB that does not compress: several IDAT chunks
        // nothing but the file itself is left in the directory (no temporaries)
        CHECK(std::distance(std::filesystem::directory_iterator(dir.path), {}) == 1);
    }
}

TEST_CASE("PNG of a rendered-looking picture round trips and deflates", "[splat]") {
    // a flat background and a shaded disc: the writer's one zlib stream must both round trip and
    // compress (libpng checks every chunk's CRC and the stream's Adler-32 on reading)
    test::TempDir dir("png");
    Image img;
    img.width = 301;
    img.height = 199;
    img.rgb.assign(3 * img.width * img.height, 0);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            std::uint8_t* p = img.rgb.data() + 3 * (static_cast<std::size_t>(y) * img.width + x);
            const int dx = x - 150, dy = y - 100, r2 = dx * dx + dy * dy;
            p[0] = 30;
            p[1] = 40;
            p[2] = 60;
            if (r2 < 80 * 80) p[0] = p[1] = p[2] = static_cast<std::uint8_t>(255 - r2 / 40);
        }
    const std::string path = (dir / "disc.png").string();
    write_png(img, path);
    const Image back = read_png(path);
    CHECK(back.width == img.width);
    CHECK(back.height == img.height);
    CHECK(back.rgb == img.rgb);
    CHECK(std::filesystem::file_size(path) < img.rgb.size() / 10);
    CHECK(checked_chunks(path, std::size_t{1} << 20) == std::vector<std::string>{"IHDR", "IDAT", "IEND"});
}

TEST_CASE("PNG writing into a missing directory throws IoError naming the path and leaves nothing", "[splat]") {
    test::TempDir dir("png");
    Image img;
    img.width = img.height = 4;
    img.rgb.assign(48, 128);
    const std::string path = (dir / "missing" / "out.png").string();
    try {
        write_png(img, path);
        FAIL("expected IoError");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find(path) != std::string::npos);
    }
    CHECK_FALSE(std::filesystem::exists(dir / "missing"));
    CHECK(std::distance(std::filesystem::directory_iterator(dir.path), {}) == 0);
}

TEST_CASE("PNG reader rejects a non-PNG file and a truncated PNG", "[splat]") {
    test::TempDir dir("png");
    const std::string bad = (dir / "bad.png").string();
    std::ofstream(bad) << "this is not a png file at all";
    CHECK_THROWS_AS(read_png(bad), FormatError);
    CHECK_THROWS_AS(read_png((dir / "absent.png").string()), IoError);

    Image img;
    img.width = 64;
    img.height = 64;
    img.rgb.resize(3 * 64 * 64);
    for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = static_cast<std::uint8_t>(i * 7);
    const std::string good = (dir / "good.png").string();
    write_png(img, good);
    const auto size = std::filesystem::file_size(good);
    std::filesystem::resize_file(good, size / 2);
    CHECK_THROWS_AS(read_png(good), FormatError);

    Image wrong = img;
    wrong.rgb.pop_back();
    CHECK_THROWS_AS(write_png(wrong, (dir / "wrong.png").string()), InvalidArgument);
}
