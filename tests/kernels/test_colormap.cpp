#include <catch2/catch.hpp>

#include <cmath>

#include "kernels/colormap.hpp"

using namespace meshless;

TEST_CASE("colour maps: ends, clamping, NaN, monotone gray", "[colormap]") {
    CHECK(map_color(Colormap::coolwarm, 0, 0, 1) == std::array<std::uint8_t, 3>{59, 76, 192});
    CHECK(map_color(Colormap::coolwarm, 1, 0, 1) == std::array<std::uint8_t, 3>{180, 4, 38});
    CHECK(map_color(Colormap::coolwarm, 5, 0, 1) == map_color(Colormap::coolwarm, 1, 0, 1));
    CHECK(map_color(Colormap::coolwarm, std::nan(""), 0, 1) == std::array<std::uint8_t, 3>{128, 128, 128});
    int last = -1;
    for (int i = 0; i <= 100; ++i) {
        const int g = map_color(Colormap::gray, i / 100.0, 0, 1)[0];
        CHECK(g >= last);
        last = g;
    }
    Colormap m;
    CHECK(parse_colormap("gray", m));
    CHECK(!parse_colormap("jet", m));
}
