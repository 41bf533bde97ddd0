// Comparison of two rendered pictures (dissertation section 6.6, Figure 6.6 d/e: a LOD's volume
// rendering differenced with the full-resolution one): root-mean-square error and peak
// signal-to-noise ratio over all 8-bit channels, and a difference picture.
//     RMSE = sqrt(mean over pixels and channels of (a - b)^2)      (grey levels, 0..255)
//     PSNR = 20 log10(255 / RMSE) dB                                (+infinity when RMSE = 0)
// Throws InvalidArgument when the sizes differ or a pixel buffer does not match its size, or for a
// gain that is not positive and finite. Pure, reentrant.
#pragma once
#include <cstdint>

#include "kernels/splat_rasterizer.hpp"

namespace meshless {

struct ImageDifference {
    double rmse = 0;                   ///< grey levels
    double psnr = 0;                   ///< dB; +infinity for identical pictures
    int max_abs = 0;                   ///< largest channel difference
    std::uint64_t differing_pixels = 0;  ///< pixels with any channel different
};

ImageDifference compare_images(const Image& a, const Image& b);

/// |a - b| per channel times `gain` (clamped to 255): black where the pictures agree.
Image difference_image(const Image& a, const Image& b, double gain = 1.0);

}  // namespace meshless
