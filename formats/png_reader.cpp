#include "formats/png_reader.hpp"
#include "formats/binary_file.hpp"

#include <png.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

/// Frees the simplified-API state on every path out.
struct PngImageGuard {
    png_image* img;
    ~PngImageGuard() { png_image_free(img); }
};

}  // namespace

Image decode_png(std::span<const unsigned char> bytes, const std::string& name) {
    if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0) throw FormatError(name + ": not a PNG (bad signature)");
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    PngImageGuard guard{&img};
    if (!png_image_begin_read_from_memory(&img, bytes.data(), bytes.size()))
        throw FormatError(name + ": not a valid PNG (" + img.message + ")");
    if (img.width < 1 || img.height < 1 || img.width > kMaxPngSide || img.height > kMaxPngSide)
        throw FormatError(name + ": image size " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                          " outside 1..16384 per side");
    // The scanlines (at least one filter byte and 1 bit per pixel each) come out of deflate, which
    // expands at most 1032:1: more than that cannot be in this many bytes.
    const std::uint64_t min_raw = static_cast<std::uint64_t>(img.height) * (1 + (static_cast<std::uint64_t>(img.width) + 7) / 8);
    if (min_raw > 1032 * static_cast<std::uint64_t>(bytes.size()) + 4096)
        throw FormatError(name + ": header claims " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                          " pixels, more than its " + std::to_string(bytes.size()) + " bytes can hold (truncated or damaged)");
    img.format = PNG_FORMAT_RGB;
    Image out;
    out.width = static_cast<int>(img.width);
    out.height = static_cast<int>(img.height);
    out.rgb.resize(3 * static_cast<std::size_t>(img.width) * img.height);
    if (!png_image_finish_read(&img, nullptr, out.rgb.data(), 0, nullptr))
        throw FormatError(name + ": corrupt PNG data (" + img.message + ")");
    return out;
}

Image read_png(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a PNG file");
    require_regular_file(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw IoError(path + ": read error");
    return decode_png(bytes, path);
}

}  // namespace meshless
