#include "kernels/anatomical_view.hpp"

#include <cmath>

namespace meshless {

AnatomicalView anatomical_view(const std::array<Vec3, 3>& lps, double turn_azimuth_deg, double turn_elevation_deg) {
    AnatomicalView v;
    // superior is LPS +z: the axis whose direction has the largest |z|
    int up = 0;
    for (int a = 1; a < 3; ++a)
        if (std::fabs(lps[a].z) > std::fabs(lps[up].z)) up = a;
    v.up_axis = up;
    v.up_negative = lps[up].z < 0;
    // anterior is LPS -y: of the other axes, the one with the largest |y|
    int front = up == 0 ? 1 : 0;
    for (int a = 0; a < 3; ++a)
        if (a != up && std::fabs(lps[a].y) > std::fabs(lps[front].y)) front = a;
    v.front_axis = front;
    v.front_negative = lps[front].y > 0;  // +y (posterior) along this axis: anterior is its negative side
    // the camera on the anterior side looks toward posterior
    Vec3 dir{0, 0, 0};
    const double s = v.front_negative ? 1.0 : -1.0;
    if (front == 0) dir.x = s;
    else if (front == 1) dir.y = s;
    else dir.z = s;
    double az = 0, el = 0;
    view_angles(dir, v.up_axis, v.up_negative, az, el);
    v.azimuth_deg = std::fmod(az + turn_azimuth_deg, 360.0);
    v.elevation_deg = el + turn_elevation_deg;
    return v;
}

void apply_view(const AnatomicalView& v, Camera& c) {
    c.up_axis = v.up_axis;
    c.up_negative = v.up_negative;
    c.azimuth_deg = v.azimuth_deg;
    c.elevation_deg = v.elevation_deg;
}

}  // namespace meshless
