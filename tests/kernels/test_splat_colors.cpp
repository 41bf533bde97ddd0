// Splat colours (kernels/splat_rasterizer.hpp ColorBy, kernels/colormap.hpp) and the colour bar
// legend (kernels/colorbar.hpp): the modes give different pictures, ColorBy::none is the picture
// of the default shading, unlit block colours are exactly the palette's, value colours follow the
// colour map, the bar's pixels and labels are where the layout says.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "kernels/colorbar.hpp"
#include "kernels/colormap.hpp"
#include "kernels/splat_rasterizer.hpp"

#include "fibonacci_sphere.hpp"

using namespace meshless;

namespace {

/// Points on the unit sphere (Fibonacci lattice), value = z, block = 0 for x < 0 else 1.
void sphere_points(int n, std::vector<PointRecord>& pts, std::vector<std::uint32_t>& blocks) {
    for (int i = 0; i < n; ++i) {
        const test::SpherePoint p = test::fibonacci_sphere_point(i, n);
        pts.push_back(p.rec);
        blocks.push_back(p.at.x < 0 ? 0 : 1);
    }
}

Camera cam() {
    Camera c;
    c.width = c.height = 96;
    return c;
}

std::set<std::array<std::uint8_t, 3>> colours(const Image& img, std::array<std::uint8_t, 3> bg) {
    std::set<std::array<std::uint8_t, 3>> s;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (img.at(x, y) != bg) s.insert(img.at(x, y));
    return s;
}

}  // namespace

TEST_CASE("splat colours: every mode gives another picture, none is the default picture", "[splat][color]") {
    std::vector<PointRecord> pts;
    std::vector<std::uint32_t> blocks;
    sphere_points(3000, pts, blocks);
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        INFO((k == SplatKernel::quad ? "quad" : "ewa"));
        const Image plain = render_splats(pts, cam(), k, ShadingParams{});
        std::vector<std::vector<std::uint8_t>> seen{plain.rgb};
        for (ColorBy by : {ColorBy::none, ColorBy::value, ColorBy::block, ColorBy::normal}) {
            ShadingParams s;
            s.color_by = by;
            s.value_lo = -1;
            s.value_hi = 1;
            const Image img = render_splats(pts, cam(), k, s, nullptr, {}, blocks);
            if (by == ColorBy::none) {
                CHECK(img.rgb == plain.rgb);
                continue;
            }
            for (const auto& other : seen) CHECK(img.rgb != other);
            seen.push_back(img.rgb);
        }
    }
}

TEST_CASE("splat colours: unlit block colours are exactly the palette's", "[splat][color]") {
    std::vector<PointRecord> pts;
    std::vector<std::uint32_t> blocks;
    sphere_points(3000, pts, blocks);
    ShadingParams s;
    s.color_by = ColorBy::block;
    s.ambient = 1;
    s.diffuse = 0;
    s.specular = 0;
    s.background = {255, 0, 255};
    const Image quad = render_splats(pts, cam(), SplatKernel::quad, s, nullptr, {}, blocks);
    CHECK(colours(quad, s.background) == std::set<std::array<std::uint8_t, 3>>{categorical_color(0), categorical_color(1)});
    // EWA blends the two colours along the seam x = 0; one block only: the palette colour, up to rounding
    std::vector<std::uint32_t> ones(pts.size(), 3);
    const Image ewa = render_splats(pts, cam(), SplatKernel::ewa, s, nullptr, {}, ones);
    const auto c3 = categorical_color(3);
    const auto got = colours(ewa, s.background);
    REQUIRE(!got.empty());
    for (const auto& c : got)
        for (int i = 0; i < 3; ++i) REQUIRE(std::abs(int(c[static_cast<std::size_t>(i)]) - int(c3[static_cast<std::size_t>(i)])) <= 1);
    // ids wrap around the palette
    CHECK(categorical_color(kCategoricalColors + 2) == categorical_color(2));
    CHECK(categorical_color(0) == std::array<std::uint8_t, 3>{31, 119, 180});
}

TEST_CASE("splat colours: unlit value colours follow the colour map", "[splat][color]") {
    std::vector<PointRecord> pts;
    std::vector<std::uint32_t> blocks;
    sphere_points(2000, pts, blocks);
    for (auto& p : pts) p.value = 5;  // one value: one colour, the map's at (5 - lo) / (hi - lo)
    ShadingParams s;
    s.color_by = ColorBy::value;
    s.value_lo = 0;
    s.value_hi = 10;
    s.ambient = 1;
    s.diffuse = 0;
    s.specular = 0;
    s.background = {255, 0, 255};
    const Image quad = render_splats(pts, cam(), SplatKernel::quad, s);
    CHECK(colours(quad, s.background) == std::set<std::array<std::uint8_t, 3>>{map_color(Colormap::viridis, 5, 0, 10)});
    CHECK(map_color(Colormap::viridis, 0, 0, 1) == std::array<std::uint8_t, 3>{68, 1, 84});
    CHECK(map_color(Colormap::viridis, 1, 0, 1) == std::array<std::uint8_t, 3>{253, 231, 37});
    CHECK(map_color(Colormap::viridis, 0.5, 0, 1) == std::array<std::uint8_t, 3>{33, 145, 140});
    Colormap m;
    CHECK(parse_colormap("viridis", m));
    CHECK(m == Colormap::viridis);
}

TEST_CASE("splat colours: normal colours are (n + 1) / 2", "[splat][color]") {
    PointRecord p{};
    p.normal[0] = 0;
    p.normal[1] = 0;
    p.normal[2] = 2;  // not unit: normalised
    ShadingParams s;
    s.color_by = ColorBy::normal;
    CHECK(splat_base_color(s, p, {}, 0) == ((128u << 16) | (128u << 8) | 255u));
    p.normal[2] = 0;
    CHECK(splat_base_color(s, p, {}, 0) == ((128u << 16) | (128u << 8) | 128u));  // zero normal: grey
    s.color_by = ColorBy::none;
    CHECK(splat_base_color(s, p, {}, 0) == ((226u << 16) | (214u << 8) | 190u));
}

TEST_CASE("colour bar: the bar's rows follow the map from hi (top) to lo (bottom), labels drawn", "[splat][color]") {
    Image img;
    img.width = 320;
    img.height = 240;
    img.rgb.assign(3 * 320 * 240, 0);
    draw_colorbar(img, Colormap::viridis, -2.5, 0.75);
    const ColorbarLayout l = colorbar_layout(320, 240);
    REQUIRE(l.drawn);
    CHECK(l.scale == 1);
    const int n = l.y1 - l.y0;
    CHECK(img.at(l.x0, l.y0) == map_color(Colormap::viridis, 0.75 - 0.5 / n * 3.25, -2.5, 0.75));
    CHECK(img.at(l.x1 - 1, l.y1 - 1) == map_color(Colormap::viridis, 0.75 - (n - 0.5) / n * 3.25, -2.5, 0.75));
    CHECK(img.at(l.x0 - 1, (l.y0 + l.y1) / 2) == std::array<std::uint8_t, 3>{255, 255, 255});  // frame
    // labels: white pixels above and below the bar, nothing left of the bar in its rows
    int above = 0, below = 0, left = 0;
    for (int x = 0; x < 320; ++x) {
        for (int y = 0; y < l.y0 - 1; ++y) above += img.at(x, y)[0] == 255;
        for (int y = l.y1 + 1; y < 240; ++y) below += img.at(x, y)[0] == 255;
    }
    for (int y = l.y0; y < l.y1; ++y)
        for (int x = 0; x < l.x0 - 1; ++x) left += img.at(x, y) != std::array<std::uint8_t, 3>{0, 0, 0};
    CHECK(above > 10);
    CHECK(below > 10);
    CHECK(left == 0);
    CHECK(label_width("0.75", 1) == 15);
    // too small: nothing drawn
    Image tiny;
    tiny.width = tiny.height = 40;
    tiny.rgb.assign(3 * 40 * 40, 7);
    draw_colorbar(tiny, Colormap::viridis, 0, 1);
    CHECK(std::all_of(tiny.rgb.begin(), tiny.rgb.end(), [](std::uint8_t v) { return v == 7; }));
}

namespace {
/// `s` drawn at scale 1 into a black w x 8 picture: '#' for each inked pixel, '.' for the others.
std::string label_pixels(const std::string& s, int w) {
    Image img;
    img.width = w;
    img.height = 8;
    img.rgb.assign(3 * static_cast<std::size_t>(w) * 8, 0);
    draw_label(img, 0, 0, 1, s, {255, 255, 255});
    std::string on;
    for (std::size_t i = 0; i < img.rgb.size(); i += 3) on += img.rgb[i] == 255 ? '#' : '.';
    return on;
}
}  // namespace

TEST_CASE("colour bar: the bitmap font draws digits, '-', '.', 'e', '+' and skips others", "[splat][color]") {
    auto ink_count = [](const std::string& s) {
        const std::string on = label_pixels(s, 64);
        return static_cast<int>(std::count(on.begin(), on.end(), '#'));
    };
    CHECK(ink_count("8") == 13);
    CHECK(ink_count("1") == 8);
    CHECK(ink_count("-") == 3);
    CHECK(ink_count(".") == 1);
    CHECK(ink_count("e") > 0);
    CHECK(ink_count("+") == 5);
    CHECK(ink_count("#") == 0);
    CHECK(ink_count("1e-3") == ink_count("1") + ink_count("e") + ink_count("-") + ink_count("3"));
}

TEST_CASE("colour bar: the font's letters are 26 distinct glyphs in one case (and unit letters in lower case), a title drawn above the values", "[splat][color]") {
    auto pixels = [](const std::string& s) { return label_pixels(s, 8); };
    std::set<std::string> glyphs;
    for (char c = 'A'; c <= 'Z'; ++c) {
        const std::string g = pixels(std::string(1, c));
        CHECK(g.find('#') != std::string::npos);
        glyphs.insert(g);
        // ('e' is the exponent's; c, m, n, u have lower-case glyphs of their own, for the length units)
        if (std::string("ECMNU").find(c) == std::string::npos) CHECK(pixels(std::string(1, static_cast<char>(c - 'A' + 'a'))) == g);
        else CHECK(pixels(std::string(1, static_cast<char>(c - 'A' + 'a'))) != g);
    }
    CHECK(glyphs.size() == 26);
    for (const char* c : {"_", ":", "/", "(", ")"}) CHECK(pixels(c).find('#') != std::string::npos);
    // the title: ink in the rows above the top value's label, none there without it
    auto title_ink = [](const std::string& title) {
        Image img;
        img.width = 320;
        img.height = 240;
        img.rgb.assign(3 * 320 * 240, 0);
        draw_colorbar(img, Colormap::viridis, 0, 1, {255, 255, 255}, title);
        const ColorbarLayout l = colorbar_layout(320, 240);
        int n = 0;
        for (int y = 0; y < l.y0 - 3 - 5 * l.scale - 1; ++y)
            for (int x = 0; x < 320; ++x) n += img.at(x, y)[0] == 255;
        return n;
    };
    CHECK(title_ink("") == 0);
    CHECK(title_ink("temperature") > 20);
    CHECK(title_ink("temperature") == title_ink("TEMPERATURE"));
}

TEST_CASE("block legend: one swatch of the palette per block, labelled", "[splat][color]") {
    Image img;
    img.width = 320;
    img.height = 240;
    img.rgb.assign(3 * 320 * 240, 0);
    draw_block_legend(img, 3);
    const ColorbarLayout l = colorbar_layout(320, 240);
    for (int id = 0; id < 3; ++id) {
        const int y = l.y0 + id * (6 * l.scale + 2) + 1;
        CHECK(img.at((l.x0 + l.x1) / 2, y) == categorical_color(static_cast<std::uint32_t>(id)));
    }
    CHECK(img.at((l.x0 + l.x1) / 2, l.y0 + 3 * (6 * l.scale + 2) + 1) == std::array<std::uint8_t, 3>{0, 0, 0});  // no 4th
    int ink = 0;
    for (int y = l.y0; y < l.y0 + 3 * (6 * l.scale + 2); ++y)
        for (int x = 0; x < l.x0; ++x) ink += img.at(x, y)[0] == 255;
    CHECK(ink >= 3 * 5);  // the ids 0, 1, 2
    Image all = img;
    all.rgb.assign(all.rgb.size(), 0);
    draw_block_legend(all, 0);  // unknown count: the whole palette
    CHECK(all.at((l.x0 + l.x1) / 2, l.y0 + 9 * (6 * l.scale + 2) + 1) == categorical_color(9));
}

TEST_CASE("transfer function legend: rows in the function's colours from hi to lo, the opacity as grey beside them",
          "[splat][color]") {
    const TransferFunction tf({{10, 0, 0, 1, 0}, {20, 1, 0.5, 0, 1}});
    Image img;
    img.width = 320;
    img.height = 240;
    img.rgb.assign(3 * 320 * 240, 0);
    draw_transfer_legend(img, tf, {255, 255, 255}, "density");
    const ColorbarLayout l = colorbar_layout(320, 240);
    const int n = l.y1 - l.y0;
    auto byte = [](double c) { return static_cast<std::uint8_t>(std::lround(255 * c)); };
    for (const int y : {l.y0, (l.y0 + l.y1) / 2, l.y1 - 1}) {
        const double v = 20 - (y - l.y0 + 0.5) / n * 10;
        const auto c = tf.at(v);
        CHECK(img.at(l.x0, y) == std::array<std::uint8_t, 3>{byte(c[0]), byte(c[1]), byte(c[2])});
        CHECK(img.at(l.x0 - 3, y) == std::array<std::uint8_t, 3>{byte(c[3]), byte(c[3]), byte(c[3])});
    }
    int title = 0;  // the title's ink above the top value
    for (int y = 0; y < l.y0 - 3 - 5 * l.scale - 1; ++y)
        for (int x = 0; x < 320; ++x) title += img.at(x, y)[0] == 255;
    CHECK(title > 20);
}

TEST_CASE("colour bar: values below a million print their integer digits, not an exponent", "[splat][color]") {
    // the top value's label ends at the bar's right edge: its width is where its ink starts
    auto top_label_width = [](double hi) {
        Image img;
        img.width = 320;
        img.height = 240;
        img.rgb.assign(3 * 320 * 240, 0);
        draw_colorbar(img, Colormap::viridis, 0, hi, {255, 255, 255}, "");
        const ColorbarLayout l = colorbar_layout(320, 240);
        int left = l.x1 + 1;
        for (int y = l.y0 - 3 - 5 * l.scale; y < l.y0 - 3; ++y)
            for (int x = 0; x <= l.x1; ++x)
                if (img.at(x, y)[0] == 255) left = std::min(left, x);
        return std::pair<int, int>{l.x1 + 1 - left, l.scale};
    };
    const auto [w2000, s] = top_label_width(2000);
    CHECK(w2000 == label_width("2000", s));  // not "2e+03"
    CHECK(top_label_width(3926.4).first == label_width("3926", s));
    CHECK(top_label_width(0.25).first == label_width("0.25", s));
    CHECK(top_label_width(2e7).first == label_width("2e+07", s));  // a million and more: the exponent
}
