// kernels/camera.hpp: the up axis (--up) and named views (--view) against their definitions: the up
// axis projects upward in the picture, a view direction is the camera's -z axis, and up +y is the
// former turntable camera bit for bit.
#include <catch2/catch.hpp>

#include <cmath>

#include "kernels/camera.hpp"

using namespace meshless;

namespace {
Vec3 row(const ViewTransform& v, int r) { return {v.rot[r][0], v.rot[r][1], v.rot[r][2]}; }
}  // namespace

TEST_CASE("camera: up +y is the turntable camera of section 3.6", "[camera]") {
    Camera c;
    c.azimuth_deg = 30;
    c.elevation_deg = 20;
    const ViewTransform v = make_view(c, {0, 0, 0}, {1, 1, 1});
    const double a = 30 * M_PI / 180, e = 20 * M_PI / 180;
    CHECK(v.rot[0][0] == static_cast<float>(std::cos(a)));
    CHECK(v.rot[0][1] == 0.0f);
    CHECK(v.rot[1][1] == static_cast<float>(std::cos(e)));
    CHECK(v.rot[2][0] == static_cast<float>(std::cos(e) * std::sin(a)));
}

TEST_CASE("camera: the up axis points up in the picture at elevation 0, for every axis and sign", "[camera]") {
    for (int axis = 0; axis < 3; ++axis)
        for (bool neg : {false, true})
            for (double az : {0.0, 75.0, 200.0}) {
                Camera c;
                c.up_axis = axis;
                c.up_negative = neg;
                c.azimuth_deg = az;
                c.elevation_deg = 0;
                const ViewTransform v = make_view(c, {-1, -1, -1}, {1, 1, 1});
                const double s = neg ? -1 : 1;
                const Vec3 up = axis == 0 ? Vec3{s, 0, 0} : (axis == 1 ? Vec3{0, s, 0} : Vec3{0, 0, s});
                double sx0, sy0, d0, sx1, sy1, d1;
                REQUIRE(v.project({0, 0, 0}, sx0, sy0, d0));
                REQUIRE(v.project(up * 0.5, sx1, sy1, d1));
                INFO("axis " << axis << (neg ? " negative" : "") << ", azimuth " << az);
                CHECK(sx1 == Approx(sx0).margin(1e-6));
                CHECK(sy1 < sy0 - 10);  // screen y grows downward
                // the rotation is orthonormal and right-handed
                const Vec3 x = row(v, 0), y = row(v, 1), z = row(v, 2);
                CHECK(dot(x, y) == Approx(0).margin(1e-6));
                CHECK(dot(cross(x, y), z) == Approx(1).margin(1e-6));
            }
}

TEST_CASE("camera: named views look along their direction in any up frame", "[camera]") {
    const Vec3 dirs[] = {{1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}, {-1, -1, -1}, {0, 1, 0}};
    for (int axis = 0; axis < 3; ++axis)
        for (const Vec3& d : dirs) {
            Camera c;
            c.up_axis = axis;
            view_angles(d, axis, false, c.azimuth_deg, c.elevation_deg);
            const ViewTransform v = make_view(c, {-1, -1, -1}, {1, 1, 1});
            const Vec3 back = row(v, 2), want = d * (-1.0 / norm(d));
            INFO("up axis " << axis << ", view " << d.x << "," << d.y << "," << d.z);
            CHECK(back.x == Approx(want.x).margin(1e-6));
            CHECK(back.y == Approx(want.y).margin(1e-6));
            CHECK(back.z == Approx(want.z).margin(1e-6));
        }
}
