// PNG writer/reader: round trip of pixels, atomic failure on an unwritable path, rejection of
// non-PNG input.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>

#include "formats/png_writer.hpp"
#include "kernels/errors.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;

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
        // nothing but the file itself is left in the directory (no temporaries)
        CHECK(std::distance(std::filesystem::directory_iterator(dir.path), {}) == 1);
    }
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
