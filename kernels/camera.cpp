#include "kernels/camera.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace meshless {

Vec3 ViewTransform::rotate(const Vec3& d) const {
    return {rot[0][0] * d.x + rot[0][1] * d.y + rot[0][2] * d.z,
            rot[1][0] * d.x + rot[1][1] * d.y + rot[1][2] * d.z,
            rot[2][0] * d.x + rot[2][1] * d.y + rot[2][2] * d.z};
}

Vec3 ViewTransform::to_camera(const Vec3& p) const { return rotate(p - centre); }

bool ViewTransform::project(const Vec3& p, double& sx, double& sy, double& depth) const {
    const Vec3 c = to_camera(p);
    depth = distance - c.z;
    if (!(depth > near_depth)) return false;
    const double k = pixels_per_unit(depth);
    sx = cx + k * c.x;
    sy = cy - k * c.y;
    return true;
}

namespace {

/// The orbit frame of an up axis: rows are its x', y' (= up), z' axes in world coordinates, a
/// right-handed rotation: x' = world x (world y when x is up), z' = x' cross y'. Up +y: the identity.
void orbit_frame(int up_axis, bool up_negative, double f[3][3]) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) f[r][c] = 0;
    const int i = ((up_axis % 3) + 3) % 3, n = i == 0 ? 1 : 0;
    f[0][n] = 1;
    f[1][i] = up_negative ? -1 : 1;
    f[2][0] = f[0][1] * f[1][2] - f[0][2] * f[1][1];
    f[2][1] = f[0][2] * f[1][0] - f[0][0] * f[1][2];
    f[2][2] = f[0][0] * f[1][1] - f[0][1] * f[1][0];
}

}  // namespace

void view_angles(const Vec3& dir, int up_axis, bool up_negative, double& azimuth_deg, double& elevation_deg) {
    double f[3][3];
    orbit_frame(up_axis, up_negative, f);
    const double len = norm(dir);
    const Vec3 back = len > 0 ? dir * (-1.0 / len) : Vec3{0, 0, 1};
    const double b[3] = {f[0][0] * back.x + f[0][1] * back.y + f[0][2] * back.z,
                         f[1][0] * back.x + f[1][1] * back.y + f[1][2] * back.z,
                         f[2][0] * back.x + f[2][1] * back.y + f[2][2] * back.z};
    constexpr double deg = 180.0 / std::numbers::pi;
    elevation_deg = std::asin(std::clamp(b[1], -1.0, 1.0)) * deg;
    const double h = std::hypot(b[0], b[2]);
    azimuth_deg = h > 1e-12 ? std::atan2(b[0], b[2]) * deg : 0.0;
    if (azimuth_deg < 0) azimuth_deg += 360.0;
}

ViewTransform make_view(const Camera& cam, const Vec3& lo, const Vec3& hi) {
    assert(cam.width >= 1 && cam.height >= 1 && cam.zoom > 0 && cam.fov_deg > 0 && cam.fov_deg < 180);
    constexpr double deg = std::numbers::pi / 180.0;
    ViewTransform v;
    v.width = cam.width;
    v.height = cam.height;
    v.perspective = cam.perspective;
    v.cx = 0.5 * cam.width;
    v.cy = 0.5 * cam.height;

    const Vec3 c = (lo + hi) * 0.5;
    const double r = 0.5 * norm(hi - lo);
    const bool finite = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && std::isfinite(r);
    v.centre = finite ? c : Vec3{0, 0, 0};
    v.radius = (finite && r > 0) ? r : 1.0;

    double az = std::fmod(cam.azimuth_deg, 360.0);
    if (az < 0) az += 360.0;
    const double a = az * deg, e = cam.elevation_deg * deg;
    const double sa = std::sin(a), ca = std::cos(a), se = std::sin(e), ce = std::cos(e);
    // Orbit basis: back = direction from the centre to the eye; right stays horizontal.
    const double right[3] = {ca, 0.0, -sa};
    const double up[3] = {-se * sa, ce, -se * ca};
    const double back[3] = {ce * sa, se, ce * ca};
    // rows in the orbit frame, then into world coordinates (row . F: F's rows are the frame's axes)
    double f[3][3];
    orbit_frame(cam.up_axis, cam.up_negative, f);
    const double* rows[3] = {right, up, back};
    for (int r = 0; r < 3; ++r)
        for (int i = 0; i < 3; ++i)
            v.rot[r][i] = static_cast<float>(rows[r][0] * f[0][i] + rows[r][1] * f[1][i] + rows[r][2] * f[2][i]);

    const double half_px = 0.5 * std::min(cam.width, cam.height);
    const double half_fov = 0.5 * cam.fov_deg * deg;
    // The same eye distance for both projections keeps depths comparable; the sphere fits the cone.
    v.distance = v.radius / std::sin(half_fov);
    v.near_depth = 1e-3 * v.distance;
    v.focal_px = cam.perspective ? cam.zoom * half_px / std::tan(half_fov) : cam.zoom * half_px / v.radius;
    return v;
}

}  // namespace meshless
