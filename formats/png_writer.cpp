#include "formats/png_writer.hpp"

#include <png.h>

#include <cerrno>

#include <cstring>
#include <vector>

#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

void write_png(const Image& image, const std::string& path) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != 3 * static_cast<std::size_t>(image.width) * image.height)
        throw UsageError(path + ": image " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                         " does not match its " + std::to_string(image.rgb.size()) + "-byte pixel buffer");
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = static_cast<png_uint_32>(image.width);
    img.height = static_cast<png_uint_32>(image.height);
    img.format = PNG_FORMAT_RGB;
    const png_int_32 stride = 3 * image.width;
    // encoded once, into a buffer of the worst-case size (png_image_write_get_memory_size would
    // encode the whole image a first time only to measure it)
    png_alloc_size_t size = PNG_IMAGE_PNG_SIZE_MAX(img);
    std::vector<unsigned char> buf(size);
    if (!png_image_write_to_memory(&img, buf.data(), &size, 0, image.rgb.data(), stride, nullptr))
        throw IoError(path + ": PNG encoding failed (" + img.message + ")");
    AtomicFile out(path);
    out.write(buf.data(), size);
    out.commit();
}

Image read_png(const std::string& path) {
    std::FILE* fp = std::fopen(path.c_str(), "rb");
    if (!fp) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_stdio(&img, fp)) {
        std::fclose(fp);
        throw FormatError(path + ": not a valid PNG (" + img.message + ")");
    }
    img.format = PNG_FORMAT_RGB;
    Image out;
    out.width = static_cast<int>(img.width);
    out.height = static_cast<int>(img.height);
    out.rgb.resize(PNG_IMAGE_SIZE(img));
    const bool ok = png_image_finish_read(&img, nullptr, out.rgb.data(), 0, nullptr) != 0;
    std::fclose(fp);
    if (!ok) throw FormatError(path + ": corrupt PNG data (" + img.message + ")");
    return out;
}

}  // namespace meshless
