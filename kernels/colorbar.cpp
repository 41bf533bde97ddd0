#include "kernels/colorbar.hpp"
#include "kernels/significant_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace meshless {

namespace {

/// 3x5 glyph rows (bit 2 = left column); nullptr for characters without a glyph.
const std::uint8_t* glyph(char c) {
    static constexpr std::uint8_t digits[10][5] = {
        {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
        {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};
    static constexpr std::uint8_t minus[5] = {0, 0, 7, 0, 0};
    static constexpr std::uint8_t plus[5] = {0, 2, 7, 2, 0};
    static constexpr std::uint8_t dot[5] = {0, 0, 0, 0, 2};
    static constexpr std::uint8_t e[5] = {2, 5, 7, 4, 3};  // the exponent of "%.3g" ("1e+03")
    static constexpr std::uint8_t letters[26][5] = {
        {2, 5, 7, 5, 5}, {6, 5, 6, 5, 6}, {3, 4, 4, 4, 3}, {6, 5, 5, 5, 6}, {7, 4, 6, 4, 7}, {7, 4, 6, 4, 4},
        {3, 4, 5, 5, 3}, {5, 5, 7, 5, 5}, {7, 2, 2, 2, 7}, {1, 1, 1, 5, 2}, {5, 5, 6, 5, 5}, {4, 4, 4, 4, 7},
        {5, 7, 7, 5, 5}, {6, 5, 5, 5, 5}, {2, 5, 5, 5, 2}, {6, 5, 6, 4, 4}, {2, 5, 5, 6, 3}, {6, 5, 6, 5, 5},
        {3, 4, 2, 1, 6}, {7, 2, 2, 2, 2}, {5, 5, 5, 5, 7}, {5, 5, 5, 5, 2}, {5, 5, 7, 7, 5}, {5, 5, 2, 5, 5},
        {5, 5, 2, 2, 2}, {7, 1, 2, 4, 7}};
    // the lower-case letters of the length units (kernels/axes_overlay.hpp: "mm", "um", "nm", "cm")
    static constexpr std::uint8_t lower_c[5] = {0, 0, 3, 4, 3}, lower_m[5] = {0, 0, 7, 7, 5}, lower_n[5] = {0, 0, 6, 5, 5},
                                  lower_u[5] = {0, 0, 5, 5, 7};
    static constexpr std::uint8_t underscore[5] = {0, 0, 0, 0, 7};
    static constexpr std::uint8_t colon[5] = {0, 2, 0, 2, 0};
    static constexpr std::uint8_t slash[5] = {1, 1, 2, 4, 4};
    static constexpr std::uint8_t open[5] = {1, 2, 2, 2, 1};
    static constexpr std::uint8_t close[5] = {4, 2, 2, 2, 4};
    if (c >= '0' && c <= '9') return digits[c - '0'];
    if (c == '-') return minus;
    if (c == '+') return plus;
    if (c == '.') return dot;
    if (c == 'e') return e;
    if (c >= 'A' && c <= 'Z') return letters[c - 'A'];
    if (c == 'c') return lower_c;
    if (c == 'm') return lower_m;
    if (c == 'n') return lower_n;
    if (c == 'u') return lower_u;
    if (c >= 'a' && c <= 'z') return letters[c - 'a'];  // (titles: one case, upper-cased before drawing)
    if (c == '_') return underscore;
    if (c == ':') return colon;
    if (c == '/') return slash;
    if (c == '(') return open;
    if (c == ')') return close;
    return nullptr;
}

void put(Image& img, int x, int y, std::array<std::uint8_t, 3> c) { put_pixel(img, x, y, c); }

// 3 significant digits, or as many as the integer part has below a million: 2000 and 3926 rather
// than "2e+03" and "3.93e+03" (a legend's ends read as numbers, not as exponents)
std::string format_value(double v) {
    const double a = std::fabs(v);
    const int digits = a >= 1 && a < 1e6 ? static_cast<int>(std::floor(std::log10(a))) + 1 : 0;
    return significant_text(v, std::max(3, digits));
}

}  // namespace

void put_pixel(Image& img, int x, int y, std::array<std::uint8_t, 3> c) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
    std::uint8_t* p = &img.rgb[3 * (static_cast<std::size_t>(y) * img.width + x)];
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
}

int label_width(const std::string& text, int s) { return text.empty() ? 0 : (4 * static_cast<int>(text.size()) - 1) * s; }

void draw_label(Image& img, int x, int y, int s, const std::string& text, std::array<std::uint8_t, 3> ink) {
    for (std::size_t i = 0; i < text.size(); ++i) {
        const std::uint8_t* g = glyph(text[i]);
        if (!g) continue;
        const int gx = x + 4 * s * static_cast<int>(i);
        for (int r = 0; r < 5; ++r)
            for (int col = 0; col < 3; ++col)
                if (g[r] & (4 >> col))
                    for (int dy = 0; dy < s; ++dy)
                        for (int dx = 0; dx < s; ++dx) put(img, gx + col * s + dx, y + r * s + dy, ink);
    }
}

ColorbarLayout colorbar_layout(int width, int height) {
    ColorbarLayout l;
    if (width < 48 || height < 48) return l;
    l.drawn = true;
    l.scale = std::max(1, std::min(width, height) / 160);
    l.x1 = width - 4 * l.scale - 2;
    l.x0 = l.x1 - 6 * l.scale;
    l.y0 = height / 5;
    l.y1 = 4 * height / 5;
    return l;
}

namespace {

/// The bar of `row_colour(v)` from hi (top) to lo (bottom) with its frame, values and title.
template <class RowColour>
void draw_value_bar(Image& img, double lo, double hi, std::array<std::uint8_t, 3> ink, const std::string& title, RowColour&& row_colour) {
    const ColorbarLayout l = colorbar_layout(img.width, img.height);
    if (!l.drawn || img.rgb.size() != 3 * static_cast<std::size_t>(img.width) * img.height) return;
    const int n = l.y1 - l.y0;
    for (int y = l.y0; y < l.y1; ++y) {
        const double v = hi - (y - l.y0 + 0.5) / n * (hi - lo);
        const auto c = row_colour(v, y);
        for (int x = l.x0; x < l.x1; ++x) put(img, x, y, c);
    }
    for (int x = l.x0 - 1; x <= l.x1; ++x) {
        put(img, x, l.y0 - 1, ink);
        put(img, x, l.y1, ink);
    }
    for (int y = l.y0 - 1; y <= l.y1; ++y) {
        put(img, l.x0 - 1, y, ink);
        put(img, l.x1, y, ink);
    }
    const int s = l.scale;
    const std::string top = format_value(hi), bottom = format_value(lo);
    draw_label(img, std::max(0, l.x1 + 1 - label_width(top, s)), l.y0 - 3 - 5 * s, s, top, ink);
    draw_label(img, std::max(0, l.x1 + 1 - label_width(bottom, s)), l.y1 + 3, s, bottom, ink);
    if (!title.empty()) {  // above the top value, upper case, right-aligned to the bar (from the left edge when wider)
        std::string t = title;
        for (char& c : t) c = c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c;
        draw_label(img, std::max(2, l.x1 + 1 - label_width(t, s)), l.y0 - 6 - 10 * s, s, t, ink);
    }
}

}  // namespace

void draw_colorbar(Image& img, Colormap m, double lo, double hi, std::array<std::uint8_t, 3> ink, const std::string& title) {
    draw_value_bar(img, lo, hi, ink, title, [&](double v, int) { return map_color(m, v, lo, hi); });
}

void draw_transfer_legend(Image& img, const TransferFunction& tf, std::array<std::uint8_t, 3> ink, const std::string& title) {
    const ColorbarLayout l = colorbar_layout(img.width, img.height);
    if (!l.drawn || img.rgb.size() != 3 * static_cast<std::size_t>(img.width) * img.height) return;
    auto byte = [](double c) { return static_cast<std::uint8_t>(std::lround(255 * std::clamp(c, 0.0, 1.0))); };
    const int s = l.scale;
    draw_value_bar(img, tf.lo(), tf.hi(), ink, title, [&](double v, int y) {
        const auto c = tf.at(v);
        const std::uint8_t a = byte(c[3]);  // the opacity strip left of the frame
        for (int x = l.x0 - 2 - 2 * s; x < l.x0 - 2; ++x) put(img, x, y, {a, a, a});
        return std::array<std::uint8_t, 3>{byte(c[0]), byte(c[1]), byte(c[2])};
    });
}

void draw_block_legend(Image& img, std::uint32_t blocks, std::array<std::uint8_t, 3> ink) {
    const ColorbarLayout l = colorbar_layout(img.width, img.height);
    if (!l.drawn || img.rgb.size() != 3 * static_cast<std::size_t>(img.width) * img.height) return;
    const int s = l.scale;
    const std::uint32_t n = blocks == 0 ? kCategoricalColors : std::min<std::uint32_t>(blocks, kCategoricalColors);
    for (std::uint32_t id = 0; id < n; ++id) {
        const int y0 = l.y0 + static_cast<int>(id) * (6 * s + 2);
        if (y0 + 6 * s > img.height) break;
        const auto c = categorical_color(id);
        for (int y = y0; y < y0 + 6 * s; ++y)
            for (int x = l.x0; x < l.x1; ++x) put(img, x, y, c);
        const std::string label = std::to_string(id);
        draw_label(img, l.x0 - 2 * s - label_width(label, s), y0 + s / 2, s, label, ink);
    }
}

}  // namespace meshless
