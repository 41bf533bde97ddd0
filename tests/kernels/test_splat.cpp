// Tests of the software splat renderer (dissertation section 3.6): analytic coverage of single
// splats, hole-free planes, the silhouette and shading of a sphere, depth order, permutation
// invariance, turntable periodicity.
#include <algorithm>
#include <bit>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "kernels/camera.hpp"
#include "kernels/splat_rasterizer.hpp"

using namespace meshless;

namespace {

constexpr std::array<std::uint8_t, 3> kMagenta{255, 0, 255};  // never produced by grey shading

ShadingParams test_shading() {
    ShadingParams s;
    s.background = kMagenta;
    return s;
}

PointRecord rec(Vec3 p, Vec3 n, float r) {
    PointRecord q{};
    q.pos[0] = float(p.x), q.pos[1] = float(p.y), q.pos[2] = float(p.z);
    q.normal[0] = float(n.x), q.normal[1] = float(n.y), q.normal[2] = float(n.z);
    q.radius = r;
    q.value = 0;
    return q;
}

std::int64_t covered(const Image& img, std::array<std::uint8_t, 3> bg = kMagenta) {
    std::int64_t c = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) c += img.at(x, y) != bg;
    return c;
}

double luminance(const Image& img, int x, int y) {
    const auto p = img.at(x, y);
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

const std::array<Vec3, 2> kUnitBox{Vec3{-1, -1, -1}, Vec3{1, 1, 1}};

Camera front_camera(int size, bool perspective) {
    Camera c;
    c.azimuth_deg = 0;
    c.elevation_deg = 0;
    c.width = c.height = size;
    c.perspective = perspective;
    return c;
}

// Fibonacci sphere of n points, radius rho, outward normals; splat radius = k * mean spacing.
std::vector<PointRecord> sphere_points(int n, double rho, double k) {
    std::vector<PointRecord> pts;
    pts.reserve(n);
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    const float r = float(k * rho * std::sqrt(4 * std::numbers::pi / n));
    for (int i = 0; i < n; ++i) {
        const double y = 1.0 - 2.0 * (i + 0.5) / n;
        const double s = std::sqrt(1 - y * y);
        const Vec3 d{s * std::cos(golden * i), y, s * std::sin(golden * i)};
        pts.push_back(rec(d * rho, d, r));
    }
    return pts;
}

}  // namespace

TEST_CASE("camera: azimuth turns about the y axis, 0 and 360 coincide, the box fits", "[splat]") {
    for (bool persp : {true, false}) {
        Camera c;
        c.perspective = persp;
        c.width = 320;
        c.height = 240;
        double sx0 = 0, sy0 = 0, d0 = 0;
        for (double az : {0.0, 10.0, 123.0, 360.0}) {
            c.azimuth_deg = az;
            const ViewTransform v = make_view(c, kUnitBox[0], kUnitBox[1]);
            double sx, sy, d;
            REQUIRE(v.project(Vec3{0, 0.5, 0}, sx, sy, d));  // on the rotation axis
            if (az == 0) {
                sx0 = sx, sy0 = sy, d0 = d;
            } else {
                CHECK(sx == Approx(sx0).margin(1e-4));
                CHECK(sy == Approx(sy0).margin(1e-4));
                CHECK(d == Approx(d0).margin(1e-6));
            }
            // every box corner projects inside the image
            for (int k = 0; k < 8; ++k) {
                const Vec3 p{k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0};
                REQUIRE(v.project(p, sx, sy, d));
                CHECK(sx >= 0);
                CHECK(sx <= c.width);
                CHECK(sy >= 0);
                CHECK(sy <= c.height);
            }
        }
        c.azimuth_deg = 0;
        const ViewTransform a = make_view(c, kUnitBox[0], kUnitBox[1]);
        c.azimuth_deg = 360;
        const ViewTransform b = make_view(c, kUnitBox[0], kUnitBox[1]);
        CHECK(std::memcmp(a.rot, b.rot, sizeof a.rot) == 0);
    }
}

TEST_CASE("single splat facing the camera covers (2r)^2 (quad) and pi r^2 (ewa) pixels", "[splat]") {
    for (bool persp : {true, false}) {
        const Camera cam = front_camera(256, persp);
        const ViewTransform v = make_view(cam, kUnitBox[0], kUnitBox[1]);
        for (float rho : {0.15f, 0.3f}) {
            const PointRecord p = rec({0, 0, 0}, {0, 0, 1}, rho);
            const double rpx = rho * v.pixels_per_unit(v.distance);
            INFO("perspective " << persp << " r_px " << rpx);
            REQUIRE(rpx > 8);
            SplatStats st;
            const Image q = render_splats({&p, 1}, cam, SplatKernel::quad, test_shading(), &st, kUnitBox);
            CHECK(st.splats_drawn == 1);
            CHECK(std::abs(double(covered(q)) - 4 * rpx * rpx) <= 4 * rpx + 1);
            const Image e = render_splats({&p, 1}, cam, SplatKernel::ewa, test_shading(), &st, kUnitBox);
            CHECK(st.splats_drawn == 1);
            CHECK(double(covered(e)) == Approx(std::numbers::pi * rpx * rpx).epsilon(0.05));
            // a zero normal draws as if facing the camera
            const PointRecord z = rec({0, 0, 0}, {0, 0, 0}, rho);
            for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa})
                CHECK(render_splats({&z, 1}, cam, k, test_shading(), nullptr, kUnitBox).rgb ==
                      render_splats({&p, 1}, cam, k, test_shading(), nullptr, kUnitBox).rgb);
        }
    }
}

TEST_CASE("a dense planar grid renders without holes inside its projection", "[splat]") {
    const int n = 160;
    const double h = 2.0 / (n - 1);
    std::vector<PointRecord> pts;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) pts.push_back(rec({-1 + i * h, -1 + j * h, 0}, {0, 0, 1}, float(0.75 * h)));
    Camera cam;
    cam.width = cam.height = 200;
    cam.azimuth_deg = 35;
    cam.elevation_deg = 25;
    for (bool persp : {true, false}) {
        cam.perspective = persp;
        const ViewTransform v = make_view(cam, kUnitBox[0], kUnitBox[1]);
        double cx[4], cy[4], d;
        const Vec3 corners[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
        for (int k = 0; k < 4; ++k) REQUIRE(v.project(corners[k], cx[k], cy[k], d));
        // signed distance (pixels) of a point to the projected quadrilateral's edges; > 0 inside
        auto inside = [&](double x, double y) {
            double dmin = 1e30;
            double orient = (cx[1] - cx[0]) * (cy[2] - cy[0]) - (cy[1] - cy[0]) * (cx[2] - cx[0]);
            for (int k = 0; k < 4; ++k) {
                const int l = (k + 1) % 4;
                const double ex = cx[l] - cx[k], ey = cy[l] - cy[k];
                const double s = ((x - cx[k]) * ey - (y - cy[k]) * ex) / std::hypot(ex, ey);
                dmin = std::min(dmin, orient > 0 ? -s : s);
            }
            return dmin;
        };
        for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
            const Image img = render_splats(pts, cam, k, test_shading(), nullptr, kUnitBox);
            std::int64_t holes = 0, inner = 0, stray = 0;
            for (int y = 0; y < img.height; ++y)
                for (int x = 0; x < img.width; ++x) {
                    const double s = inside(x + 0.5, y + 0.5);
                    const bool bg = img.at(x, y) == kMagenta;
                    if (s > 1.0) {
                        ++inner;
                        holes += bg;
                    }
                    if (s < -4.0) stray += !bg;  // beyond splat radius + low-pass footprint
                }
            INFO("perspective " << persp << " kernel " << int(k));
            CHECK(inner > 5000);
            CHECK(holes == 0);
            CHECK(stray == 0);
        }
    }
}

TEST_CASE("a densely sampled sphere renders as a shaded disc of the analytic size", "[splat]") {
    const double rho = 0.8;
    const auto pts = sphere_points(200000, rho, 0.9);
    Camera cam;
    cam.width = cam.height = 512;
    ShadingParams sh = test_shading();
    sh.specular = 0;  // pure Lambert under the headlight
    for (bool persp : {true, false}) {
        cam.perspective = persp;
        const ViewTransform v = make_view(cam, kUnitBox[0], kUnitBox[1]);
        // apparent radius: perspective sphere of radius rho at eye distance D: f * rho / sqrt(D^2 - rho^2)
        const double R = persp ? v.focal_px * rho / std::sqrt(v.distance * v.distance - rho * rho) : v.focal_px * rho;
        for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
            INFO("perspective " << persp << " kernel " << int(k) << " R_px " << R);
            const Image img = render_splats(pts, cam, k, sh, nullptr, kUnitBox);
            CHECK(double(covered(img)) == Approx(std::numbers::pi * R * R).epsilon(0.05));
            const int c = cam.width / 2;
            const double centre = luminance(img, c, c);
            const double mid = luminance(img, c + int(0.5 * R), c);
            const double rim = luminance(img, c + int(0.92 * R), c);
            CHECK(img.at(c + int(0.92 * R), c) != kMagenta);
            CHECK(centre > mid);
            CHECK(mid > rim);
            // Lambert under a headlight: brightness ~ ambient + diffuse * cos(angle); centre ~ full
            CHECK(centre / rim > 1.5);
            // Per pixel against the analytic shading: cast the pixel's ray at the exact sphere
            // (camera space: sphere at the origin, eye at z = D, headlight along +z).
            const double base_lum = 0.299 * sh.base[0] + 0.587 * sh.base[1] + 0.114 * sh.base[2];
            auto analytic = [&](double px, double py) {  // expected luminance at a screen point
                const double u = (px - v.cx) / v.focal_px, w = -(py - v.cy) / v.focal_px;
                Vec3 o{0, 0, v.distance}, d{0, 0, -1};
                if (persp) d = normalized(Vec3{u, w, -1});
                else o = Vec3{u, w, v.distance};
                const double b = dot(o, d), cc = dot(o, o) - rho * rho, disc = b * b - cc;
                REQUIRE(disc > 0);
                const Vec3 hit = o + d * (-b - std::sqrt(disc));
                return base_lum * (sh.ambient + sh.diffuse * std::max(0.0, hit.z / rho));
            };
            const double lum_09 = analytic(v.cx + 0.9 * R, v.cy);
            std::int64_t checked = 0, bad = 0, bright_rim = 0;
            double worst = 0;
            for (int y = 0; y < img.height; ++y)
                for (int x = 0; x < img.width; ++x) {
                    const double rad = std::hypot(x + 0.5 - v.cx, y + 0.5 - v.cy) / R;
                    if (rad > 0.9) {  // near and beyond the silhouette: never brighter than inside
                        if (img.at(x, y) != kMagenta && luminance(img, x, y) > lum_09 + 6) ++bright_rim;
                        continue;
                    }
                    const double err = std::abs(luminance(img, x, y) - analytic(x + 0.5, y + 0.5));
                    worst = std::max(worst, err);
                    ++checked;
                    bad += err > 6;
                }
            INFO("worst luminance error " << worst);
            CHECK(checked > 0.7 * std::numbers::pi * R * R);
            CHECK(bad == 0);
            CHECK(bright_rim == 0);
        }
    }
}

TEST_CASE("a nearer splat occludes a farther one regardless of draw order", "[splat]") {
    const Camera cam = front_camera(128, true);
    const PointRecord near = rec({0, 0, 0.5}, {0, 0, 1}, 0.1f);
    const PointRecord far = rec({0.05, 0, -0.5}, {0.6, 0, 0.8}, 0.3f);
    const std::vector<PointRecord> ab{near, far}, ba{far, near};
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        const Image a = render_splats(ab, cam, k, test_shading(), nullptr, kUnitBox);
        const Image b = render_splats(ba, cam, k, test_shading(), nullptr, kUnitBox);
        const Image only_near = render_splats({&near, 1}, cam, k, test_shading(), nullptr, kUnitBox);
        const Image only_far = render_splats({&far, 1}, cam, k, test_shading(), nullptr, kUnitBox);
        CHECK(a.rgb == b.rgb);
        const int c = 64;
        CHECK(a.at(c, c) == only_near.at(c, c));
        CHECK(only_near.at(c, c) != only_far.at(c, c));
        // where only the far splat reaches, it shows
        const int x = c + 7;
        REQUIRE(only_near.at(x, c) == kMagenta);
        REQUIRE(only_far.at(x, c) != kMagenta);
        CHECK(a.at(x, c) == only_far.at(x, c));
    }
}

TEST_CASE("images are deterministic and independent of the point order", "[splat]") {
    auto pts = sphere_points(50000, 0.9, 1.0);
    Camera cam;
    cam.width = cam.height = 256;
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        const Image a = render_splats(pts, cam, k, test_shading());
        const Image a2 = render_splats(pts, cam, k, test_shading());
        CHECK(a.rgb == a2.rgb);
        auto shuffled = pts;
        std::mt19937 rng(12345);
        std::shuffle(shuffled.begin(), shuffled.end(), rng);
        const Image b = render_splats(shuffled, cam, k, test_shading());
        CHECK(a.rgb == b.rgb);
    }
}

TEST_CASE("turntable: azimuth 0 equals 360, renderer reuse equals one-shot rendering", "[splat]") {
    // an asymmetric object: a sphere plus an off-axis blob
    auto pts = sphere_points(20000, 0.6, 1.0);
    for (const auto& p : sphere_points(3000, 0.2, 1.0)) {
        PointRecord q = p;
        q.pos[0] += 0.7f;
        pts.push_back(q);
    }
    Camera cam;
    cam.width = cam.height = 160;
    const auto bounds = point_bounds(pts);
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        SplatRenderer r(cam, test_shading(), bounds);
        const Image f0 = r.render(pts, k, 0.0);
        const Image f10 = r.render(pts, k, 10.0);
        const Image f360 = r.render(pts, k, 360.0);
        CHECK(f0.rgb == f360.rgb);
        CHECK(f0.rgb != f10.rgb);
        Camera c10 = cam;
        c10.azimuth_deg = 10;
        CHECK(render_splats(pts, c10, k, test_shading(), nullptr, bounds).rgb == f10.rgb);
    }
}

TEST_CASE("empty input and points behind the eye give the background", "[splat]") {
    Camera cam;
    cam.width = 40;
    cam.height = 30;
    const ShadingParams sh = test_shading();
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        const Image e = render_splats({}, cam, k, sh);
        CHECK(e.width == 40);
        CHECK(e.height == 30);
        CHECK(covered(e) == 0);
        // far behind the eye along the view axis (camera at az 0, elev 0 sits at +z)
        const PointRecord behind = rec({0, 0, 100}, {0, 0, 1}, 1.0f);
        CHECK(covered(render_splats({&behind, 1}, front_camera(40, true), k, sh, nullptr, kUnitBox)) == 0);
        PointRecord nan = rec({0, 0, 0}, {0, 0, 1}, 0.5f);
        nan.pos[1] = std::nanf("");
        CHECK(covered(render_splats({&nan, 1}, front_camera(40, true), k, sh, nullptr, kUnitBox)) == 0);
    }
}

// Scratch timing, not a test: ./test_kernels "[.splat_bench]"
TEST_CASE("splat frame time for ~1M splats at 800x800", "[.splat_bench]") {
    const auto pts = sphere_points(1000000, 0.9, 1.0);
    Camera cam;
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        SplatRenderer r(cam, ShadingParams{}, point_bounds(pts));
        SplatStats st;
        double best = 1e30, total = 0;
        const int frames = 6;
        for (int i = 0; i < frames; ++i) {
            r.render(pts, k, 10.0 * i, &st);
            best = std::min(best, st.seconds);
            total += st.seconds;
        }
        std::printf("%s: 1M splats 800x800: best %.3f s, mean %.3f s, %lld splats drawn, %lld fragments\n",
                    k == SplatKernel::quad ? "quad" : "ewa", best, total / frames, (long long)st.splats_drawn,
                    (long long)st.fragments);
    }
}

TEST_CASE("SplatFrame: partial buffers over any split of the points, merged, equal one pass", "[splat]") {
    std::vector<PointRecord> pts = sphere_points(4000, 0.7, 1.3);
    const auto more = sphere_points(1500, 0.45, 1.5);
    pts.insert(pts.end(), more.begin(), more.end());
    std::mt19937 rng(5);
    std::shuffle(pts.begin(), pts.end(), rng);
    const Camera cam = front_camera(90, true);
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        const Image ref = render_splats(pts, cam, k, test_shading(), nullptr, kUnitBox);
        const SplatFrame f(cam, k, test_shading(), kUnitBox);
        const std::size_t n = f.npix();
        // three uneven parts, each drawn into its own buffer
        const std::size_t cut[4] = {0, 17, 3001, pts.size()};
        std::vector<std::vector<std::uint64_t>> keys(3, std::vector<std::uint64_t>(n, SplatFrame::kEmptyKey));
        SplatStats st;
        for (int p = 0; p < 3; ++p)
            f.draw(std::span(pts).subspan(cut[p], cut[p + 1] - cut[p]), keys[p].data(), st);
        for (int p = 1; p < 3; ++p) SplatFrame::merge_keys(keys[0].data(), keys[p].data(), n);
        std::vector<std::vector<std::int64_t>> acc(3, std::vector<std::int64_t>(4 * n, 0));
        if (f.two_pass()) {
            for (int p = 0; p < 3; ++p)
                f.accumulate(std::span(pts).subspan(cut[p], cut[p + 1] - cut[p]), keys[0].data(), acc[p].data(), st);
            for (int p = 1; p < 3; ++p) SplatFrame::merge_acc(acc[0].data(), acc[p].data(), 4 * n);
        }
        Image img;
        f.resolve(keys[0].data(), acc[0].data(), img);
        CHECK(covered(img) > 1000);
        CHECK(img.rgb == ref.rgb);
        // without the merge (one part only) the picture differs: the comparison can fail
        Image part;
        std::vector<std::uint64_t> k1(n, SplatFrame::kEmptyKey);
        f.draw(std::span(pts).subspan(0, 3001), k1.data(), st);
        std::vector<std::int64_t> a1(4 * n, 0);
        if (f.two_pass()) f.accumulate(std::span(pts).subspan(0, 3001), k1.data(), a1.data(), st);
        f.resolve(k1.data(), a1.data(), part);
        CHECK(part.rgb != ref.rgb);
    }
}

namespace {
// The records every early exit of an EWA footprint meets, `copies` times: NaN / infinite positions,
// zero and NaN normals, zero, negative, NaN and infinite radii, a point behind the eye, one far off
// screen.
void add_degenerate_records(std::vector<PointRecord>& pts, int copies) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    for (int i = 0; i < copies; ++i) {
        pts.push_back(rec({NAN, 0, 0}, {0, 0, 1}, 0.05f));
        pts.push_back(rec({0.1, inf, 0}, {0, 0, 1}, 0.05f));
        pts.push_back(rec({0.2, 0.1 * i, 0.85}, {0, 0, 0}, 0.05f));
        pts.push_back(rec({-0.2, 0.1 * i, 0.85}, {nan, 0, 1}, 0.05f));
        pts.push_back(rec({0.3, -0.1 * i, 0.85}, {0, 1, 1}, 0.0f));
        pts.push_back(rec({0.3, -0.1 * i, 0.86}, {1, 0, 1}, -0.05f));
        pts.push_back(rec({0.35, 0.1 * i, 0.86}, {1, 0, 1}, nan));
        pts.push_back(rec({0.35, 0.1 * i, 0.87}, {1, 1, 0}, inf));
        pts.push_back(rec({0, 0, 50}, {0, 0, 1}, 0.05f));
        pts.push_back(rec({40, 0, 0}, {0, 0, 1}, 0.05f));
    }
}

// Pass 1 written out plainly, one pixel at a time, from the footprints draw() hands out: the oracle
// of the (vectorised) visibility pass.
std::vector<std::uint64_t> plain_visibility(const std::vector<EwaFootprint>& fps, int W, int H, float c2) {
    std::vector<std::uint64_t> keys(static_cast<std::size_t>(W) * H, SplatFrame::kEmptyKey);
    for (const EwaFootprint& f : fps) {
        std::uint64_t packed = 0;
        for (float c : f.n) packed = (packed << 10) | static_cast<std::uint64_t>(std::lrint(std::clamp(c, -1.0f, 1.0f) * 511.0f + 511.0f));
        const float zlo = std::max(f.depth - f.radius, 0.0f), zhi = f.depth + f.radius;
        for (int y = f.y0; y <= f.y1; ++y)
            for (int x = f.x0; x <= f.x1; ++x) {
                const float dx = x + 0.5f - f.sx, dy = y + 0.5f - f.sy;
                const float q = f.q00 * dx * dx + 2.0f * f.q01 * dx * dy + f.q11 * dy * dy;
                if (q > c2) continue;
                const float z = std::clamp(f.depth + f.gx * dx + f.gy * dy, zlo, zhi);
                std::uint64_t& k = keys[static_cast<std::size_t>(y) * W + x];
                k = std::min(k, (std::uint64_t{std::bit_cast<std::uint32_t>(z)} << 32) | packed);
            }
    }
    return keys;
}
}  // namespace

TEST_CASE("EWA pass 2 from spooled footprints and with hidden splats skipped: the same sums as from the points", "[splat]") {
    // three nested spheres seen from outside, shuffled: most splats are hidden behind the outer one
    std::vector<PointRecord> pts = sphere_points(6000, 0.8, 1.3);
    for (double rho : {0.6, 0.4}) {
        const auto more = sphere_points(3000, rho, 1.4);
        pts.insert(pts.end(), more.begin(), more.end());
    }
    // and records every early exit of the footprint meets
    add_degenerate_records(pts, 8);
    std::mt19937 rng(11);
    std::shuffle(pts.begin(), pts.end(), rng);
    for (ColorBy colour : {ColorBy::none, ColorBy::normal})
        for (bool perspective : {true, false}) {
            INFO("colour " << int(colour) << " perspective " << perspective);
            ShadingParams sh = test_shading();
            sh.color_by = colour;
            const Camera cam = front_camera(150, perspective);
            const SplatFrame f(cam, SplatKernel::ewa, sh, kUnitBox);
            const std::size_t n = f.npix(), words = f.acc_words();
            std::vector<std::uint64_t> keys(n, SplatFrame::kEmptyKey);
            std::vector<EwaFootprint> fps, part;
            SplatStats st;
            // drawn in two parts; the footprints of each part, concatenated
            const std::size_t cut = 5000;
            f.draw(std::span(pts).first(cut), keys.data(), st);
            f.footprints(std::span(pts).first(cut), fps);
            f.draw(std::span(pts).subspan(cut), keys.data(), st);
            f.footprints(std::span(pts).subspan(cut), part);
            fps.insert(fps.end(), part.begin(), part.end());
            REQUIRE(static_cast<std::int64_t>(fps.size()) == st.splats_drawn);
            {
                // one point at a time (the scalar footprint) gives the bytes of the batched (SIMD) one,
                // and so do all points at once
                std::vector<std::uint64_t> k1(n, SplatFrame::kEmptyKey);
                std::vector<EwaFootprint> one, all, whole;
                SplatStats s1;
                for (std::size_t i = 0; i < pts.size(); ++i) {
                    f.draw(std::span(pts).subspan(i, 1), k1.data(), s1);
                    f.footprints(std::span(pts).subspan(i, 1), one);
                    all.insert(all.end(), one.begin(), one.end());
                }
                REQUIRE(all.size() == fps.size());
                CHECK(std::memcmp(all.data(), fps.data(), fps.size() * sizeof(EwaFootprint)) == 0);
                CHECK(k1 == keys);
                f.footprints(pts, whole);
                REQUIRE(whole.size() == fps.size());
                CHECK(std::memcmp(whole.data(), fps.data(), fps.size() * sizeof(EwaFootprint)) == 0);
            }
            REQUIRE(st.splats_drawn > 10000);
            {
                // pass 1 from the footprints, culled: the same keys nearest first, farthest first and
                // in two key buffers merged; nearest first skips most splats (the inner ones)
                std::vector<EwaFootprint> near = fps;
                std::stable_sort(near.begin(), near.end(), [](const EwaFootprint& a, const EwaFootprint& b) { return a.depth < b.depth; });
                std::vector<EwaFootprint> far(near.rbegin(), near.rend());
                std::vector<std::uint64_t> kn(n, SplatFrame::kEmptyKey), kf(n, SplatFrame::kEmptyKey),
                    k2(n, SplatFrame::kEmptyKey), k3(n, SplatFrame::kEmptyKey);
                SplatStats sn, sf, s2;
                EwaCull cn, cf, c2, c3;
                f.draw(near, kn.data(), sn, &cn);
                f.draw(far, kf.data(), sf, &cf);
                f.draw(std::span(far).first(far.size() / 3), k2.data(), s2, &c2);
                f.draw(std::span(far).subspan(far.size() / 3), k3.data(), s2, &c3);
                SplatFrame::merge_keys(k2.data(), k3.data(), n);
                CHECK(kn == keys);
                CHECK(kf == keys);
                CHECK(k2 == keys);
                CHECK(sn.splats_drawn < st.splats_drawn / 2);
                CHECK(sf.splats_drawn > sn.splats_drawn);
            }
            // the visibility pass equals its plain per-pixel form
            CHECK(plain_visibility(fps, f.width(), f.height(), float(sh.ewa_cutoff * sh.ewa_cutoff)) == keys);

            const VisibleDepthTiles tiles = f.depth_tiles(keys.data());
            std::vector<std::int64_t> ref(words * n, 0), a(words * n, 0), b(words * n, 0), c(words * n, 0);
            SplatStats s_ref, s_a, s_b, s_c;
            f.accumulate(pts, keys.data(), ref.data(), s_ref);                    // every splat, from the points
            f.accumulate(pts, keys.data(), a.data(), s_a, {}, &tiles);             // hidden ones skipped
            f.accumulate(fps, keys.data(), b.data(), s_b);                         // from the footprints
            std::reverse(fps.begin(), fps.end());                                  // any order
            f.accumulate(fps, keys.data(), c.data(), s_c, &tiles);
            CHECK(a == ref);
            CHECK(b == ref);
            CHECK(c == ref);
            CHECK(s_b.fragments == s_ref.fragments);
            // the skip does skip (most fragments are behind the outer sphere), and the sums are not trivial
            CHECK(s_a.fragments < s_ref.fragments / 2);
            CHECK(s_c.fragments == s_a.fragments);
            std::int64_t covered_px = 0;
            for (std::size_t i = 0; i < n; ++i) covered_px += ref[words * i] != 0;
            CHECK(covered_px > 3000);  // covered pixels (the outer disc: about 4000 of 22500)
        }
}

TEST_CASE("visible-depth tiles: the largest depth per tile, empty pixels never hide", "[splat]") {
    const Camera cam = front_camera(21, true);  // 21 is no multiple of the tile size: partial tiles
    const SplatFrame f(cam, SplatKernel::ewa, test_shading(), kUnitBox);
    const int W = 21, T = VisibleDepthTiles::kSize;
    std::vector<std::uint64_t> keys(f.npix(), 0);
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x)
            keys[static_cast<std::size_t>(y) * W + x] = std::uint64_t{std::bit_cast<std::uint32_t>(float((x * 7) % 11 + 100 * y))} << 32 | 7u;
    keys[1] = SplatFrame::kEmptyKey;                                                  // tile (0, 0)
    keys[static_cast<std::size_t>(T) * W + T] = std::uint64_t{0x80000000u} << 32;  // -0.0: tile (1, 1)
    const VisibleDepthTiles t = f.depth_tiles(keys.data());
    const int n = (W + T - 1) / T;
    REQUIRE(t.tiles_x == n);
    REQUIRE(t.tiles_y == n);
    for (int ty = 0; ty < n; ++ty)
        for (int tx = 0; tx < n; ++tx) {
            INFO("tile " << tx << ", " << ty);
            const float got = t.max_depth[static_cast<std::size_t>(ty) * n + tx];
            if ((tx == 0 && ty == 0) || (tx == 1 && ty == 1)) {
                CHECK(std::isinf(got));
                continue;
            }
            float want = 0;
            for (int y = ty * T; y < std::min(W, ty * T + T); ++y)
                for (int x = tx * T; x < std::min(W, tx * T + T); ++x) want = std::max(want, float((x * 7) % 11 + 100 * y));
            CHECK(got == want);
        }
}

TEST_CASE("EWA: the AVX2 loops give the bits of the baseline SSE2 ones", "[splat]") {
    // Splats of every size (sub-pixel to ~60 pixels wide, so rows of every length and every masked
    // tail), random orientations, overlapping in depth, plus the records every early exit meets; an
    // image of odd sides, so rows end at every lane.
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), r01(0.0f, 1.0f);
    std::vector<PointRecord> pts;
    for (int i = 0; i < 6000; ++i) {
        const float rad = 0.002f * std::pow(150.0f, r01(rng));  // 0.002 .. 0.3
        pts.push_back(rec({0.9 * u(rng), 0.9 * u(rng), 0.9 * u(rng)}, {u(rng), u(rng), u(rng)}, rad));
    }
    add_degenerate_records(pts, 3);
    for (int i = 0; i < 3; ++i) pts.push_back(rec({0.95, 0.95, 0.2 + 0.1 * i}, {0, 0, 1}, 0.2f));  // cut by the image's corner
    std::shuffle(pts.begin(), pts.end(), rng);
    bool compared_avx2 = false;
    for (ColorBy colour : {ColorBy::none, ColorBy::normal})
        for (bool perspective : {true, false}) {
            INFO("colour " << int(colour) << " perspective " << perspective);
            ShadingParams sh = test_shading();
            sh.color_by = colour;
            Camera cam = front_camera(97, perspective);
            cam.height = 61;
            cam.azimuth_deg = 17;
            const SplatFrame best(cam, SplatKernel::ewa, sh, kUnitBox);
            SplatFrame base(cam, SplatKernel::ewa, sh, kUnitBox);
            base.use_baseline_isa();
            CHECK(std::string(base.ewa_isa()) != "avx2");
            compared_avx2 = compared_avx2 || std::string(best.ewa_isa()) == "avx2";
            const std::size_t n = best.npix(), words = best.acc_words();

            std::vector<EwaFootprint> fa, fb;
            best.footprints(pts, fa);
            base.footprints(pts, fb);
            REQUIRE(fa.size() == fb.size());
            REQUIRE(fa.size() > 5000);
            CHECK(std::memcmp(fa.data(), fb.data(), fa.size() * sizeof(EwaFootprint)) == 0);

            // pass 1 from the points and from the footprints (culled, nearest first)
            std::vector<std::uint64_t> ka(n, SplatFrame::kEmptyKey), kb(n, SplatFrame::kEmptyKey),
                kc(n, SplatFrame::kEmptyKey);
            SplatStats sa, sb, sc;
            best.draw(pts, ka.data(), sa);
            base.draw(pts, kb.data(), sb);
            std::vector<EwaFootprint> near = fa;
            std::stable_sort(near.begin(), near.end(), [](const EwaFootprint& a, const EwaFootprint& b) { return a.depth < b.depth; });
            EwaCull cull;
            best.draw(near, kc.data(), sc, &cull);
            CHECK(ka == kb);
            CHECK(kc == kb);
            CHECK(sa.fragments == sb.fragments);
            CHECK(plain_visibility(fb, base.width(), base.height(), float(sh.ewa_cutoff * sh.ewa_cutoff)) == kb);

            // pass 2 from the points and from the footprints, with and without the tiles
            const VisibleDepthTiles tiles = base.depth_tiles(kb.data());
            CHECK(best.depth_tiles(kb.data()).max_depth == tiles.max_depth);
            // the tile scan on keys of every kind: depths, empty, -0, +infinity, NaN, sparse
            std::vector<std::uint64_t> odd(n);
            for (std::size_t i = 0; i < n; ++i) {
                const std::uint32_t kinds[] = {std::bit_cast<std::uint32_t>(r01(rng) * 10.0f), 0xFFFFFFFFu, 0x80000000u,
                                               0x7F800000u, 0x7FC00000u, 0u};
                const std::uint32_t hi = r01(rng) < 0.9f ? kinds[0] : kinds[rng() % 6];
                odd[i] = (std::uint64_t{hi} << 32) | (rng() & 0x3FFFFFFFu);
            }
            const VisibleDepthTiles ta_odd = best.depth_tiles(odd.data()), tb_odd = base.depth_tiles(odd.data());
            CHECK(ta_odd.tiles_x == tb_odd.tiles_x);
            CHECK(std::memcmp(ta_odd.max_depth.data(), tb_odd.max_depth.data(), ta_odd.max_depth.size() * sizeof(float)) == 0);
            std::vector<std::int64_t> aa(words * n, 0), ab(words * n, 0), ac(words * n, 0), ad(words * n, 0);
            SplatStats ta, tb, tc, td;
            best.accumulate(pts, kb.data(), aa.data(), ta);
            base.accumulate(pts, kb.data(), ab.data(), tb);
            best.accumulate(fa, kb.data(), ac.data(), tc, &tiles);
            base.accumulate(fb, kb.data(), ad.data(), td, &tiles);
            CHECK(aa == ab);
            CHECK(ac == ab);
            CHECK(ad == ab);
            CHECK(ta.fragments == tb.fragments);
            CHECK(tc.fragments == td.fragments);
            std::int64_t blended = 0;  // pixels that blend more than one fragment (the sums are not trivial)
            for (std::size_t i = 0; i < n; ++i) blended += ab[words * i] > (std::int64_t{1} << 20);
            CHECK(blended > 500);

            Image ia, ib;
            best.resolve(ka.data(), aa.data(), ia);
            base.resolve(kb.data(), ab.data(), ib);
            CHECK(ia.rgb == ib.rgb);
        }
    if (!compared_avx2) WARN("this CPU has no AVX2: the baseline loops were compared with themselves");
}

TEST_CASE("point bounds: the first of equal extremes in any split, non-finite positions ignored", "[splat]") {
    // the sequential double fold of the definition: std::min/std::max keep the first of equal values
    std::mt19937 rng(41);
    std::uniform_int_distribution<int> pick(0, 9);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    // two sets: one with extremes away from zero, one whose extremes are +0 and -0 (which of the
    // equal zeros is kept shows in the bits)
    const float wide[] = {0.0f, -0.0f, 1.5f, -2.25f, nan, inf, -inf, 3.0f, -0.0f, 0.0f};
    const float zeros[] = {0.0f, -0.0f, nan, inf, -inf, -0.0f, 0.0f, 0.0f, -0.0f, nan};
    for (const float* values : {wide, zeros}) {
        std::vector<PointRecord> pts(257);
        for (PointRecord& p : pts)
            for (float& c : p.pos) c = values[pick(rng)];
        double lo[3], hi[3];
        bool any = false;
        for (const PointRecord& p : pts) {
            if (!(std::isfinite(p.pos[0]) && std::isfinite(p.pos[1]) && std::isfinite(p.pos[2]))) continue;
            for (int i = 0; i < 3; ++i) {
                lo[i] = any ? std::min(lo[i], double(p.pos[i])) : double(p.pos[i]);
                hi[i] = any ? std::max(hi[i], double(p.pos[i])) : double(p.pos[i]);
            }
            any = true;
        }
        REQUIRE(any);
        for (std::size_t split : {std::size_t{1}, std::size_t{7}, std::size_t{64}, pts.size()}) {
            INFO("parts of " << split);
            PointBounds b;
            for (std::size_t at = 0; at < pts.size(); at += split)
                b.add(std::span<const PointRecord>(pts).subspan(at, std::min(split, pts.size() - at)));
            const auto got = b.bounds();
            for (int i = 0; i < 3; ++i) {
                CHECK(std::bit_cast<std::uint64_t>(got[0][i]) == std::bit_cast<std::uint64_t>(lo[i]));
                CHECK(std::bit_cast<std::uint64_t>(got[1][i]) == std::bit_cast<std::uint64_t>(hi[i]));
            }
        }
    }
    // only non-finite positions: the empty bounds
    std::vector<PointRecord> bad(5);
    for (PointRecord& p : bad) p.pos[1] = nan;
    PointBounds none;
    none.add(bad);
    CHECK(none.bounds()[0][0] == 0.0);
    CHECK(none.bounds()[1][2] == 0.0);
}
