#include "kernels/image_compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

void check_pair(const Image& a, const Image& b) {
    auto fits = [](const Image& i) {
        return i.width >= 0 && i.height >= 0 && i.rgb.size() == 3 * static_cast<std::size_t>(i.width) * static_cast<std::size_t>(i.height);
    };
    if (!fits(a) || !fits(b)) throw InvalidArgument("image comparison: a pixel buffer does not match its image size");
    if (a.width != b.width || a.height != b.height)
        throw InvalidArgument("image comparison: sizes differ (" + std::to_string(a.width) + "x" + std::to_string(a.height) +
                              " and " + std::to_string(b.width) + "x" + std::to_string(b.height) + ")");
}

}  // namespace

ImageDifference compare_images(const Image& a, const Image& b) {
    check_pair(a, b);
    ImageDifference d;
    std::uint64_t sum = 0;  // at most 255^2 * 3 * 16384^2: fits in 64 bits
    const std::size_t n = a.rgb.size();
    for (std::size_t i = 0; i < n; i += 3) {
        bool differs = false;
        for (std::size_t c = 0; c < 3; ++c) {
            const int e = std::abs(static_cast<int>(a.rgb[i + c]) - static_cast<int>(b.rgb[i + c]));
            sum += static_cast<std::uint64_t>(e * e);
            d.max_abs = std::max(d.max_abs, e);
            differs = differs || e != 0;
        }
        d.differing_pixels += differs ? 1 : 0;
    }
    d.rmse = n ? std::sqrt(static_cast<double>(sum) / static_cast<double>(n)) : 0.0;
    d.psnr = d.rmse > 0 ? 20.0 * std::log10(255.0 / d.rmse) : std::numeric_limits<double>::infinity();
    return d;
}

Image difference_image(const Image& a, const Image& b, double gain) {
    check_pair(a, b);
    if (!(gain > 0) || !std::isfinite(gain)) throw InvalidArgument("difference image: gain must be positive and finite");
    Image out;
    out.width = a.width;
    out.height = a.height;
    out.rgb.resize(a.rgb.size());
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
        const double e = std::abs(static_cast<double>(a.rgb[i]) - static_cast<double>(b.rgb[i])) * gain;
        out.rgb[i] = static_cast<std::uint8_t>(std::min(255.0, std::round(e)));
    }
    return out;
}

}  // namespace meshless
