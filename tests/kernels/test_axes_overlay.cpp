// The axes triad and scale bar (kernels/axes_overlay.hpp): round lengths, the bar's pixel length at
// the framed centre's scale, the axes' colours where the camera shows them, nothing on tiny pictures.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "kernels/axes_overlay.hpp"

using namespace meshless;

namespace {

Image black(int w, int h) {
    Image img;
    img.width = w;
    img.height = h;
    img.rgb.assign(3 * static_cast<std::size_t>(w) * h, 0);
    return img;
}

}  // namespace

TEST_CASE("axes overlay: the scale bar's length is the largest 1, 2 or 5 x 10^k not above the target", "[kernels][axes]") {
    CHECK(scale_bar_length(37) == 20);
    CHECK(scale_bar_length(0.7) == 0.5);
    CHECK(scale_bar_length(1) == 1);
    CHECK(scale_bar_length(9.99) == 5);
    CHECK(scale_bar_length(10) == 10);
    CHECK(scale_bar_length(2e-6) == Approx(2e-6));
    CHECK(scale_bar_length(0) == 0);
    CHECK(scale_bar_length(-3) == 0);
    CHECK(scale_bar_length(NAN) == 0);
}

TEST_CASE("axes overlay: the bar spans its length at the view's scale, the axes in their colours", "[kernels][axes]") {
    for (const bool perspective : {false, true}) {
        Camera cam;
        cam.width = 320;
        cam.height = 240;
        cam.perspective = perspective;
        const ViewTransform v = make_view(cam, Vec3{0, 0, 0}, Vec3{100, 50, 30});
        Image img = black(320, 240);
        draw_axes(img, v);
        const int s = 1, y = 240 - 8 * s - 4;
        int x0 = 320, x1 = -1;
        for (int x = 0; x < 320; ++x)
            if (img.at(x, y) == std::array<std::uint8_t, 3>{255, 255, 255}) {
                x0 = std::min(x0, x);
                x1 = std::max(x1, x);
            }
        const double k = v.pixels_per_unit(v.distance);
        const double length = scale_bar_length(320 / 5.0 / k);
        INFO("perspective " << perspective << ": bar " << x0 << ".." << x1 << ", " << length << " units at " << k << " px/unit");
        REQUIRE(x1 > x0);
        CHECK(std::abs((x1 - x0) - length * k) <= 2.0);  // (the pen is 2 pixels wide)
        CHECK(length * k <= 320 / 5.0 + 1e-9);
        CHECK(length * k > 320 / 5.0 / 2.5 - 1e-9);       // a round length within a factor 2.5 below a fifth
        // the triad's three colours appear in the bottom-left corner, nowhere else
        int colours[3] = {0, 0, 0}, elsewhere = 0;
        for (int yy = 0; yy < 240; ++yy)
            for (int x = 0; x < 320; ++x) {
                const auto c = img.at(x, yy);
                const int which = c == std::array<std::uint8_t, 3>{235, 70, 70} ? 0 : c == std::array<std::uint8_t, 3>{80, 205, 80} ? 1
                                  : c == std::array<std::uint8_t, 3>{90, 140, 255}                                               ? 2
                                                                                                                                  : -1;
                if (which < 0) continue;
                if (x < 60 && yy > 180) ++colours[which];
                else ++elsewhere;
            }
        CHECK(colours[0] > 5);
        CHECK(colours[1] > 5);
        CHECK(colours[2] > 5);
        CHECK(elsewhere == 0);
    }
    Image tiny = black(40, 40);
    Camera cam;
    draw_axes(tiny, make_view(cam, Vec3{0, 0, 0}, Vec3{1, 1, 1}));
    CHECK(std::all_of(tiny.rgb.begin(), tiny.rgb.end(), [](std::uint8_t v) { return v == 0; }));
}
