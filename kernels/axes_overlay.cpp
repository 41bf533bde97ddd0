#include "kernels/axes_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "kernels/colorbar.hpp"

namespace meshless {

namespace {

/// A line from (x0, y0) to (x1, y1), `t` pixels thick (a t x t square at each step).
void line(Image& img, double x0, double y0, double x1, double y1, int t, std::array<std::uint8_t, 3> c) {
    const int steps = std::max(1, static_cast<int>(std::ceil(std::max(std::abs(x1 - x0), std::abs(y1 - y0)))));
    for (int i = 0; i <= steps; ++i) {
        const double f = static_cast<double>(i) / steps;
        const int x = static_cast<int>(std::lround(x0 + f * (x1 - x0))), y = static_cast<int>(std::lround(y0 + f * (y1 - y0)));
        for (int dy = 0; dy < t; ++dy)
            for (int dx = 0; dx < t; ++dx) put_pixel(img, x + dx - t / 2, y + dy - t / 2, c);
    }
}

}  // namespace

double scale_bar_length(double target) {
    if (!(target > 0) || !std::isfinite(target)) return 0;
    const double p = std::pow(10.0, std::floor(std::log10(target)));
    for (const double m : {5.0, 2.0, 1.0})
        if (m * p <= target * (1 + 1e-12)) return m * p;
    return p;
}

void draw_axes(Image& img, const ViewTransform& v, std::array<std::uint8_t, 3> ink, const std::string& unit) {
    if (img.width < 48 || img.height < 48 || img.rgb.size() != 3 * static_cast<std::size_t>(img.width) * img.height) return;
    const int s = std::max(1, std::min(img.width, img.height) / 160);
    // the triad
    const double arm = 12.0 * s + 4, ox = 14.0 * s + 6, oy = img.height - 14.0 * s - 6;
    static constexpr std::array<std::array<std::uint8_t, 3>, 3> kColour = {{{235, 70, 70}, {80, 205, 80}, {90, 140, 255}}};
    static constexpr const char* kName[3] = {"X", "Y", "Z"};
    for (int a = 0; a < 3; ++a) {
        Vec3 e{0, 0, 0};
        (a == 0 ? e.x : a == 1 ? e.y : e.z) = 1;
        const Vec3 d = v.rotate(e);  // camera x right, y up
        const double ex = ox + arm * d.x, ey = oy - arm * d.y;
        line(img, ox, oy, ex, ey, s, kColour[static_cast<std::size_t>(a)]);
        const double len = std::hypot(d.x, d.y);
        // the label beyond the arm's end, kept inside the picture (an arm pointing left or down)
        const double lx = std::clamp(ex + (len > 1e-6 ? d.x / len : 0) * 3 * s - 1.5 * s, 1.0, img.width - 4.0 * s);
        const double ly = std::clamp(ey - (len > 1e-6 ? d.y / len : 0) * 3 * s - 2.5 * s, 1.0, img.height - 6.0 * s);
        draw_label(img, static_cast<int>(std::lround(lx)), static_cast<int>(std::lround(ly)), s, kName[a], kColour[static_cast<std::size_t>(a)]);
    }
    // the scale bar: pixels per world unit at the framed centre's depth
    const double k = v.pixels_per_unit(v.distance);
    if (!(k > 0) || !std::isfinite(k)) return;
    const double length = scale_bar_length(img.width / 5.0 / k);
    const double px = length * k;
    if (!(px >= 4)) return;
    const double y = img.height - 8.0 * s - 4, x0 = 0.5 * (img.width - px), x1 = x0 + px;
    line(img, x0, y, x1, y, 2 * s, ink);
    line(img, x0, y - 2 * s, x0, y + s, s, ink);
    line(img, x1, y - 2 * s, x1, y + s, s, ink);
    char number[32];
    std::snprintf(number, sizeof number, "%g", length);
    const std::string text = unit.empty() ? std::string(number) : std::string(number) + " " + unit;
    draw_label(img, static_cast<int>(std::lround(0.5 * (img.width - label_width(text, s)))), static_cast<int>(y) - 3 * s - 5 * s, s, text, ink);
}

}  // namespace meshless
