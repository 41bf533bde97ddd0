#include "camera_options.hpp"

#include <cmath>
#include <vector>

#include <pybind11/pybind11.h>

#include "kernels/anatomical_view.hpp"

namespace meshless::python {

namespace py = pybind11;

namespace {

double finite(std::optional<double> v, double fallback, const char* what) {
    const double x = v.value_or(fallback);
    if (!std::isfinite(x)) throw py::value_error(std::string(what) + ": expected a finite number of degrees");
    return x;
}

Vec3 view_direction(const std::string& view) {
    if (view == "iso") return Vec3{-1, -1, -1};
    if (view.size() == 2 && (view[0] == '+' || view[0] == '-') && view[1] >= 'x' && view[1] <= 'z') {
        Vec3 dir{0, 0, 0};
        const double s = view[0] == '+' ? 1.0 : -1.0;
        if (view[1] == 'x') dir.x = s;
        else if (view[1] == 'y') dir.y = s;
        else dir.z = s;
        return dir;
    }
    throw py::value_error("view: expected '+x', '-x', '+y', '-y', '+z', '-z' or 'iso', got '" + view + "'");
}

void set_view(Camera& c, const Vec3& dir, const std::string& name, bool warn, std::vector<std::string>* warnings) {
    view_angles(dir, c.up_axis, c.up_negative, c.azimuth_deg, c.elevation_deg);
    if (warn && warnings && dir[c.up_axis] != 0 && dir[(c.up_axis + 1) % 3] == 0 && dir[(c.up_axis + 2) % 3] == 0)
        warnings->push_back("view " + name + " looks along the up axis: the picture's up is arbitrary; give another up");
}

}  // namespace

Camera camera_of(const CameraOptions& o, std::vector<std::string>* warnings) {
    Camera c;
    if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
        throw py::value_error("size: expected (width, height) in 1..16384 pixels each");
    c.width = o.width;
    c.height = o.height;
    c.azimuth_deg = finite(o.azimuth, 30, "azimuth");
    c.elevation_deg = finite(o.elevation, 20, "elevation");
    if (o.up) {
        const std::string& up = *o.up;
        const bool neg = !up.empty() && up[0] == '-';
        const std::string axis = up.substr(neg || (!up.empty() && up[0] == '+') ? 1 : 0);
        if (axis != "x" && axis != "y" && axis != "z") throw py::value_error("up: expected 'x', 'y', 'z', '-x', '-y' or '-z', got '" + up + "'");
        c.up_axis = axis[0] - 'x';
        c.up_negative = neg;
    }
    if (o.view) {
        if (o.azimuth || o.elevation) throw py::value_error("view " + *o.view + " sets the camera's direction: drop azimuth/elevation");
        set_view(c, view_direction(*o.view), *o.view, o.up.has_value(), warnings);
    }
    if (!(o.zoom > 0) || !std::isfinite(o.zoom)) throw py::value_error("zoom: expected a number > 0");
    c.zoom = o.zoom;
    c.perspective = !o.ortho;
    return c;
}

void apply_anatomical(const CameraOptions& o, const AnatomicalFrame& f, Camera& c, std::vector<std::string>* warnings) {
    if (o.up) return;  // the caller chose the camera's up
    const AnatomicalView av = anatomical_view(f.axis, c.azimuth_deg, c.elevation_deg);
    if (o.view) {  // the view names the direction, the header keeps superior up
        c.up_axis = av.up_axis;
        c.up_negative = av.up_negative;
        set_view(c, view_direction(*o.view), *o.view, true, warnings);
        return;
    }
    apply_view(av, c);
}

}  // namespace meshless::python
