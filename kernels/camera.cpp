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
    for (int i = 0; i < 3; ++i) {
        v.rot[0][i] = static_cast<float>(right[i]);
        v.rot[1][i] = static_cast<float>(up[i]);
        v.rot[2][i] = static_cast<float>(back[i]);
    }

    const double half_px = 0.5 * std::min(cam.width, cam.height);
    const double half_fov = 0.5 * cam.fov_deg * deg;
    // The same eye distance for both projections keeps depths comparable; the sphere fits the cone.
    v.distance = v.radius / std::sin(half_fov);
    v.near_depth = 1e-3 * v.distance;
    v.focal_px = cam.perspective ? cam.zoom * half_px / std::tan(half_fov) : cam.zoom * half_px / v.radius;
    return v;
}

}  // namespace meshless
