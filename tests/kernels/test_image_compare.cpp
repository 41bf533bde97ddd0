// Picture comparison (kernels/image_compare.hpp): RMSE/PSNR against hand computation, PSNR of
// identical pictures infinite, difference pictures, size mismatches refused.
#include <catch2/catch.hpp>

#include <cmath>

#include "kernels/errors.hpp"
#include "kernels/image_compare.hpp"

using namespace meshless;

namespace {
Image make(int w, int h, std::uint8_t v) {
    Image i;
    i.width = w;
    i.height = h;
    i.rgb.assign(3 * static_cast<std::size_t>(w) * h, v);
    return i;
}
}  // namespace

TEST_CASE("PSNR of identical pictures is infinite and RMSE zero", "[render]") {
    const Image a = make(7, 5, 42);
    const ImageDifference d = compare_images(a, a);
    CHECK(d.rmse == 0);
    CHECK(std::isinf(d.psnr));
    CHECK(d.psnr > 0);
    CHECK(d.differing_pixels == 0);
    CHECK(d.max_abs == 0);
}

TEST_CASE("RMSE and PSNR match the definition", "[render]") {
    const Image a = make(2, 2, 100);
    Image b = a;
    b.rgb[4] = 110;  // one channel of pixel 1 off by 10
    b.rgb[9] = 97;   // pixel 3 off by 3
    const ImageDifference d = compare_images(a, b);
    const double rmse = std::sqrt((100.0 + 9.0) / 12.0);
    CHECK(d.rmse == Approx(rmse));
    CHECK(d.psnr == Approx(20 * std::log10(255 / rmse)));
    CHECK(d.max_abs == 10);
    CHECK(d.differing_pixels == 2);
    const Image diff = difference_image(a, b, 2.0);
    CHECK(diff.rgb[4] == 20);
    CHECK(diff.rgb[9] == 6);
    CHECK(diff.rgb[0] == 0);
    CHECK(difference_image(make(1, 1, 0), make(1, 1, 255), 4.0).rgb[0] == 255);  // clamped
}

TEST_CASE("comparing pictures of different sizes is refused", "[render]") {
    CHECK_THROWS_AS(compare_images(make(2, 2, 0), make(2, 3, 0)), InvalidArgument);
    Image broken = make(2, 2, 0);
    broken.rgb.pop_back();
    CHECK_THROWS_AS(compare_images(broken, make(2, 2, 0)), InvalidArgument);
    CHECK_THROWS_AS(difference_image(make(2, 2, 0), make(2, 2, 0), 0.0), InvalidArgument);
}
