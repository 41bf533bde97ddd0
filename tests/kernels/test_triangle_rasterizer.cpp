// Triangle rasterizer (kernels/triangle_rasterizer.hpp): a marching-cubes sphere covers the analytic
// sphere's silhouette and is brightest where its normal faces the headlight; triangles sharing
// edges cover every pixel of their union exactly once (top-left fill rule).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

#include "kernels/camera.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/splitmix.hpp"
#include "kernels/triangle_rasterizer.hpp"

using namespace meshless;

namespace {

/// Marching cubes of the distance field |p - c| at iso R on an n^3 unit grid.
Mesh ball_mesh(int n, const Vec3& c, double R) {
    GridSpec g;
    g.dims = {n, n, n};
    Volume v(g, SampleType::f32);
    float* p = reinterpret_cast<float*>(v.bytes.data());
    for (std::int64_t k = 0; k < n; ++k)
        for (std::int64_t j = 0; j < n; ++j)
            for (std::int64_t i = 0; i < n; ++i)
                p[g.index(i, j, k)] = static_cast<float>(norm(Vec3{double(i), double(j), double(k)} - c));
    return marching_cubes(v.view(), R);
}

int luminance(const Image& img, int x, int y) {
    const auto c = img.at(x, y);
    return c[0] + c[1] + c[2];
}

}  // namespace

TEST_CASE("triangle rasterizer: a marching-cubes sphere covers the analytic silhouette, lit from the headlight",
          "[kernels][triangles]") {
    const Vec3 c{23.5, 23.5, 23.5};
    const double R = 19.0;
    const Mesh mesh = ball_mesh(48, c, R);
    REQUIRE(mesh.triangle_count() > 1000);
    Camera cam;
    cam.width = cam.height = 256;
    const std::array<Vec3, 2> box{c - Vec3{R, R, R}, c + Vec3{R, R, R}};
    for (const bool persp : {true, false}) {
        INFO("perspective " << persp);
        cam.perspective = persp;
        ShadingParams sh;
        TriangleStats st;
        const Image img = render_triangles(mesh, cam, sh, box, &st);
        REQUIRE(img.width == 256);
        REQUIRE(img.height == 256);
        CHECK(st.triangles_drawn > 1000);
        const ViewTransform view = make_view(cam, box[0], box[1]);
        const Vec3 cc = view.to_camera(c);
        std::int64_t both = 0, either = 0;
        int best = -1, bx = 0, by = 0;
        for (int y = 0; y < 256; ++y)
            for (int x = 0; x < 256; ++x) {
                const double dx = (x + 0.5 - view.cx) / view.focal_px, dy = -(y + 0.5 - view.cy) / view.focal_px;
                bool inside;
                if (persp) {
                    // ray from the eye (0, 0, distance) along (dx, dy, -1)
                    const Vec3 d = normalized(Vec3{dx, dy, -1});
                    const Vec3 e{0, 0, view.distance};
                    const Vec3 w = cc - e;
                    inside = norm(cross(w, d)) < R;
                } else {
                    inside = std::hypot(dx - cc.x, dy - cc.y) < R;
                }
                const auto px = img.at(x, y);
                const bool drawn = px[0] != 0 || px[1] != 0 || px[2] != 0;
                both += inside && drawn;
                either += inside || drawn;
                if (drawn && luminance(img, x, y) > best) {
                    best = luminance(img, x, y);
                    bx = x;
                    by = y;
                }
            }
        const double iou = double(both) / double(either);
        INFO("IoU " << iou);
        CHECK(iou >= 0.98);
        // The headlight: the brightest pixel is where the sphere's normal points to the light (0, 0, 1).
        const Vec3 top = cc + Vec3{0, 0, R};
        const double k = view.pixels_per_unit(view.distance - top.z);
        const double ex = view.cx + k * top.x, ey = view.cy - k * top.y;
        INFO("brightest at " << bx << "," << by << ", expected " << ex << "," << ey);
        CHECK(std::hypot(bx + 0.5 - ex, by + 0.5 - ey) < 6.0);
        // darker towards the silhouette
        const double kc = view.pixels_per_unit(view.distance - cc.z);
        const int rim = luminance(img, static_cast<int>(view.cx + kc * (cc.x + 0.9 * R)), static_cast<int>(ey));
        CHECK(rim < best - 60);
    }
}

TEST_CASE("triangle rasterizer: triangles sharing edges cover each pixel of their union exactly once",
          "[kernels][triangles]") {
    // A jittered planar grid in z = 0, seen along -z: its border is the square [0, 10]^2, its inner
    // vertices are jittered, so edges run at every slope, and some vertices sit on pixel centres.
    const int n = 10;
    Mesh m;
    SplitMix rng{7};
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            double x = i, y = j;
            if (i > 0 && i < n && j > 0 && j < n) {
                x += 0.35 * (rng.unit() * 2 - 1);
                y += 0.35 * (rng.unit() * 2 - 1);
            }
            m.xyz.insert(m.xyz.end(), {float(x), float(y), 0.0f});
            m.normals.insert(m.normals.end(), {0.0f, 0.0f, 1.0f});
        }
    auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            // alternate the diagonal and the winding
            if ((i + j) % 2) {
                m.tri.insert(m.tri.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                m.tri.insert(m.tri.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            } else {
                m.tri.insert(m.tri.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
                m.tri.insert(m.tri.end(), {at(i + 1, j + 1), at(i + 1, j), at(i, j + 1)});
            }
        }
    Camera cam;
    cam.azimuth_deg = 0;
    cam.elevation_deg = 0;
    cam.width = 173;
    cam.height = 131;
    for (const bool persp : {false, true}) {
        INFO("perspective " << persp);
        cam.perspective = persp;
        const std::array<Vec3, 2> box{Vec3{0, 0, 0}, Vec3{double(n), double(n), 0}};
        std::vector<std::uint32_t> cover;
        TriangleStats st;
        render_triangles(m, cam, ShadingParams{}, box, &st, &cover);
        const ViewTransform view = make_view(cam, box[0], box[1]);
        double x0, y0, x1, y1, d;
        REQUIRE(view.project(Vec3{0, 0, 0}, x0, y0, d));
        REQUIRE(view.project(Vec3{double(n), double(n), 0}, x1, y1, d));
        // the plane faces the camera: world x right, world y up (screen y down)
        REQUIRE(x0 < x1);
        REQUIRE(y1 < y0);
        std::int64_t inside = 0, once = 0, bad = 0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const std::uint32_t c = cover[static_cast<std::size_t>(y) * cam.width + x];
                const double px = x + 0.5, py = y + 0.5;
                const bool in = px > x0 + 1e-3 && px < x1 - 1e-3 && py > y1 + 1e-3 && py < y0 - 1e-3;
                const bool out = px < x0 - 1e-3 || px > x1 + 1e-3 || py < y1 - 1e-3 || py > y0 + 1e-3;
                if (c > 1 || (in && c != 1) || (out && c != 0)) ++bad;
                inside += in;
                once += c == 1;
            }
        CHECK(inside > 5000);
        CHECK(bad == 0);
        CHECK(st.fragments == once);
    }
}

TEST_CASE("triangle rasterizer: two triangles sharing an edge through pixel centres", "[kernels][triangles]") {
    // Orthographic, the square framed about the image centre: its diagonal x + y = 64 px passes exactly
    // through pixel centres, each of which belongs to exactly one of the two triangles.
    Mesh m;
    m.xyz = {0, 0, 0, 8, 0, 0, 8, 8, 0, 0, 8, 0};
    m.tri = {0, 1, 2, 0, 2, 3};
    Camera cam;
    cam.azimuth_deg = 0;
    cam.elevation_deg = 0;
    cam.perspective = false;
    cam.width = cam.height = 64;
    std::vector<std::uint32_t> both, a, b;
    const std::array<Vec3, 2> box{Vec3{0, 0, 0}, Vec3{8, 8, 0}};
    render_triangles(m, cam, ShadingParams{}, box, nullptr, &both);
    Mesh ma = m, mb = m;
    ma.tri = {0, 1, 2};
    mb.tri = {0, 2, 3};
    render_triangles(ma, cam, ShadingParams{}, box, nullptr, &a);
    render_triangles(mb, cam, ShadingParams{}, box, nullptr, &b);
    std::int64_t shared = 0, covered = 0;
    for (std::size_t i = 0; i < both.size(); ++i) {
        REQUIRE(both[i] <= 1);
        REQUIRE(both[i] == a[i] + b[i]);
        shared += a[i] && b[i];
        covered += both[i];
    }
    CHECK(shared == 0);
    // no crack: every pixel centre inside the square (its border passes through no centre) is covered
    const ViewTransform view = make_view(cam, box[0], box[1]);
    double x0, y0, x1, y1, d;
    REQUIRE(view.project(Vec3{0, 0, 0}, x0, y0, d));
    REQUIRE(view.project(Vec3{8, 8, 0}, x1, y1, d));
    std::int64_t expected = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) expected += x + 0.5 > x0 && x + 0.5 < x1 && y + 0.5 > y1 && y + 0.5 < y0;
    CHECK(expected > 500);
    CHECK(covered == expected);
}

TEST_CASE("triangle rasterizer: mesh bounds", "[kernels][triangles]") {
    Mesh m;
    m.xyz = {1, 2, 3, -1, 5, 0, std::nanf(""), 0, 0};
    const auto b = mesh_bounds(m);
    CHECK(b[0].x == -1);
    CHECK(b[0].y == 2);
    CHECK(b[0].z == 0);
    CHECK(b[1].x == 1);
    CHECK(b[1].y == 5);
    CHECK(b[1].z == 3);
    CHECK(mesh_bounds(Mesh{})[1].x == 0);
}
