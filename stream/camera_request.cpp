#include "stream/camera_request.hpp"

#include <cmath>

#include "kernels/anatomical_view.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

Vec3 named_view_direction(const CameraRequest& r) {
    const std::string& v = *r.view;
    if (v == "iso") return Vec3{-1, -1, -1};
    if (v.size() == 2 && (v[0] == '+' || v[0] == '-') && v[1] >= 'x' && v[1] <= 'z') {
        Vec3 dir{0, 0, 0};
        const double s = v[0] == '+' ? 1.0 : -1.0;
        if (v[1] == 'x') dir.x = s;
        else if (v[1] == 'y') dir.y = s;
        else dir.z = s;
        return dir;
    }
    throw InvalidArgument(r.option_prefix + "view: expected +x, -x, +y, -y, +z, -z or iso, got '" + v + "'");
}

// looking along the up axis leaves the picture's up to chance: say so (the camera then takes
// azimuth 0 about the up axis, a fixed but arbitrary roll)
void look_along(const CameraRequest& r, const Vec3& dir, Camera& c, bool warn_up, const CameraWarning& warn) {
    view_angles(dir, c.up_axis, c.up_negative, c.azimuth_deg, c.elevation_deg);
    if (warn_up && warn && dir[c.up_axis] != 0 && dir[(c.up_axis + 1) % 3] == 0 && dir[(c.up_axis + 2) % 3] == 0)
        warn(r.option_prefix + "view " + *r.view + " looks along the up axis (" + (c.up_negative ? "-" : "") +
             static_cast<char>('x' + c.up_axis) + "): the picture's up is arbitrary; give " + r.option_prefix + "up another axis");
}

double degrees(const std::optional<double>& v, double fallback, const CameraRequest& r, const char* name) {
    const double x = v.value_or(fallback);
    if (!std::isfinite(x)) throw InvalidArgument(r.option_prefix + name + ": expected a finite number of degrees");
    return x;
}

}  // namespace

Camera request_camera(const CameraRequest& r, const CameraWarning& warn) {
    Camera c;
    if (r.width < 1 || r.width > 16384 || r.height < 1 || r.height > 16384)
        throw InvalidArgument(r.option_prefix + "size: expected 1..16384 pixels each way, got " + std::to_string(r.width) + "x" +
                              std::to_string(r.height));
    c.width = r.width;
    c.height = r.height;
    c.azimuth_deg = degrees(r.azimuth, 30, r, "azimuth");
    c.elevation_deg = degrees(r.elevation, 20, r, "elevation");
    if (r.up) {
        const std::string& up = *r.up;
        const bool neg = !up.empty() && up[0] == '-';
        const std::string axis = up.substr(neg || (!up.empty() && up[0] == '+') ? 1 : 0);
        if (axis != "x" && axis != "y" && axis != "z")
            throw InvalidArgument(r.option_prefix + "up: expected x, y, z, -x, -y or -z, got '" + up + "'");
        c.up_axis = axis[0] - 'x';
        c.up_negative = neg;
    }
    if (r.view) {
        if (r.azimuth || r.elevation)
            throw InvalidArgument(r.option_prefix + "view " + *r.view + " sets the camera's direction: drop " + r.option_prefix +
                                  "azimuth/" + r.option_prefix + "elevation");
        look_along(r, named_view_direction(r), c, r.up.has_value(), warn);
    }
    if (!(r.zoom > 0 && r.zoom <= 1e6)) throw InvalidArgument(r.option_prefix + "zoom: expected a number in (0, 1e+06]");
    c.zoom = r.zoom;
    c.perspective = !r.ortho;
    return c;
}

void apply_anatomical_camera(const CameraRequest& r, const AnatomicalFrame& f, Camera& c, const CameraWarning& warn) {
    if (r.up) return;  // the caller chose the camera's up
    const AnatomicalView av = anatomical_view(f.axis, c.azimuth_deg, c.elevation_deg);
    if (r.view) {  // the view names the direction, the header keeps superior up
        c.up_axis = av.up_axis;
        c.up_negative = av.up_negative;
        look_along(r, named_view_direction(r), c, true, warn);
        return;
    }
    apply_view(av, c);
}

}  // namespace meshless
