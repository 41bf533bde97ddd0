// A colour bar legend drawn into a rendered picture (meshless splat / isosurface --png --colorbar):
// a vertical bar of the colour map at the right edge, value hi at its top and lo at its bottom,
// framed by a 1-pixel border, with the two values printed (printf "%.Ng", N = 3 or the digits of an
// integer part below a million: 2000, not 2e+03) above and below it in
// a built-in 3x5 bitmap font (digits, letters in one case but c, m, n, u also in lower case for the
// length units, '-', '+', '.', '_', ':', '/', '(', ')';
// other characters are left blank), and a title (the array's name) above them when given.
// Layout (colorbar_layout): scale s = max(1, min(W, H) / 160); bar width 6s, from y = H/5 to
// y = 4H/5 (exclusive), right edge 4s + 2 pixels from the image's right edge. Pictures smaller than
// 48 x 48 pixels get no bar (nothing drawn).
// Pure, reentrant, no allocation beyond the label strings; throws nothing but std::bad_alloc.
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "kernels/colormap.hpp"
#include "kernels/transfer_function.hpp"
#include "kernels/splat_rasterizer.hpp"

namespace meshless {

struct ColorbarLayout {
    bool drawn = false;
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;  ///< the bar's colour pixels: [x0, x1) x [y0, y1)
    int scale = 1;                       ///< font pixel size
};

ColorbarLayout colorbar_layout(int width, int height);

/// The colour of bar row y (y0 <= y < y1): map_color(m, hi - (y - y0 + 0.5) / (y1 - y0) * (hi - lo), lo, hi).
/// `title` (may be empty): drawn in upper case above the top value, right-aligned to the bar.
void draw_colorbar(Image& img, Colormap m, double lo, double hi, std::array<std::uint8_t, 3> ink = {255, 255, 255},
                   const std::string& title = {});

/// The transfer function's legend (`render --colorbar`): the bar's rows in the function's colours
/// from tf.hi() (top) to tf.lo() (bottom), beside it on the left a strip 2s wide whose grey level is
/// the opacity (white: opaque), the two values and `title` (may be empty) as draw_colorbar's.
void draw_transfer_legend(Image& img, const TransferFunction& tf, std::array<std::uint8_t, 3> ink = {255, 255, 255},
                          const std::string& title = {});

/// The block legend (--color block --colorbar): one swatch per palette colour in use, categorical_color(0)
/// ... categorical_color(n - 1) with n = min(blocks, kCategoricalColors) (blocks 0: all of them),
/// stacked from the bar's top (colorbar_layout's x0..x1, 6s + 2 pixels apart, each 6s tall), each
/// labelled with its id at its left; ids >= kCategoricalColors reuse the colours (id modulo 10).
void draw_block_legend(Image& img, std::uint32_t blocks, std::array<std::uint8_t, 3> ink = {255, 255, 255});

/// Sets pixel (x, y) to `c`; pixels outside the picture are skipped.
void put_pixel(Image& img, int x, int y, std::array<std::uint8_t, 3> c);

/// Draws `text` with its top-left corner at (x, y), each font pixel s x s image pixels (clipped).
void draw_label(Image& img, int x, int y, int s, const std::string& text, std::array<std::uint8_t, 3> ink);
/// Width in pixels of `text` drawn at scale s (4 font pixels per character, minus the last gap).
int label_width(const std::string& text, int s);

}  // namespace meshless
