#include "kernels/colormap.hpp"

#include <algorithm>
#include <cmath>

namespace meshless {

namespace {
// Moreland (2009) cool-to-warm, RGB at t = 0, 1/8, ..., 1
constexpr double kCoolWarm[9][3] = {{59, 76, 192},   {98, 130, 234},  {141, 176, 254}, {184, 208, 249}, {221, 221, 221},
                                    {245, 196, 173}, {244, 154, 123}, {222, 96, 77},   {180, 4, 38}};
// matplotlib viridis at t = 0, 1/8, ..., 1
constexpr double kViridis[9][3] = {{68, 1, 84},    {71, 45, 123},  {59, 82, 139},   {44, 114, 142}, {33, 145, 140},
                                   {40, 174, 128}, {94, 201, 98},  {173, 220, 48},  {253, 231, 37}};
// Tableau 10
constexpr std::uint8_t kTab10[10][3] = {{31, 119, 180}, {255, 127, 14},  {44, 160, 44},   {214, 39, 40},  {148, 103, 189},
                                        {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
}  // namespace

std::array<std::uint8_t, 3> categorical_color(std::uint32_t id) {
    const auto* c = kTab10[id % kCategoricalColors];
    return {c[0], c[1], c[2]};
}

bool parse_colormap(std::string_view s, Colormap& out) {
    if (s == "viridis") out = Colormap::viridis;
    else if (s == "coolwarm") out = Colormap::coolwarm;
    else if (s == "gray" || s == "grey") out = Colormap::gray;
    else return false;
    return true;
}

std::array<std::uint8_t, 3> map_color(Colormap m, double v, double lo, double hi, std::array<std::uint8_t, 3> nan) {
    if (std::isnan(v)) return nan;
    double t = hi > lo ? (v - lo) / (hi - lo) : 0.5;
    t = std::clamp(t, 0.0, 1.0);
    if (m == Colormap::gray) {
        const auto g = static_cast<std::uint8_t>(std::lround(255 * t));
        return {g, g, g};
    }
    const auto& table = m == Colormap::viridis ? kViridis : kCoolWarm;
    const double x = t * 8;
    const int i = std::min(7, static_cast<int>(x));
    const double f = x - i;
    std::array<std::uint8_t, 3> c{};
    for (int k = 0; k < 3; ++k)
        c[k] = static_cast<std::uint8_t>(std::lround(table[i][k] + f * (table[i + 1][k] - table[i][k])));
    return c;
}

}  // namespace meshless
