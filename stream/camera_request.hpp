// The camera of a picture from what a front end was given: the CLI's --size, --azimuth,
// --elevation, --up, --view, --zoom and --ortho, the Python module's keywords of the same names. A
// camera orbits the frame's centre (kernels/camera.hpp, dissertation section 3.6): degrees about
// the up axis and above the plane normal to it, or a named view along an axis; a volume whose header
// gives the patient's axes is drawn head up, face to the viewer (kernels/anatomical_view.hpp),
// turned by the azimuth and elevation, unless the up axis was given.
// Units: pixels (size), degrees (azimuth, elevation), a factor (zoom).
// Throws InvalidArgument naming the option (with the front end's prefix: "--view" or "view") for a
// value out of its domain; warnings (one line each, no prefix) go to the caller's callback.
#pragma once
#include <functional>
#include <optional>
#include <string>

#include "formats/anatomical_frame.hpp"
#include "kernels/camera.hpp"

namespace meshless {

/// The options as given (nullopt: not given, the default).
struct CameraRequest {
    int width = 800, height = 800;             ///< 1..16384 each
    std::optional<double> azimuth, elevation;  ///< degrees, finite; 30 and 20 when not given
    std::optional<std::string> up;             ///< "x", "y", "z", "-x", "-y", "-z" ("+x" too); y when not given
    std::optional<std::string> view;           ///< "+x" ... "-z", "iso"; excludes azimuth and elevation
    double zoom = 1;                           ///< (0, 1e6]
    bool ortho = false;
    std::string option_prefix = "--";          ///< how the front end spells an option in messages
};

/// A one-line warning of the camera (a view along the up axis).
using CameraWarning = std::function<void(const std::string& line)>;

/// The camera the request describes, checked.
Camera request_camera(const CameraRequest& r, const CameraWarning& warn = {});

/// The default for data whose header gives the patient's axes: head up, face to the viewer, turned
/// by the camera's azimuth and elevation (a named view keeps its direction, superior up); nothing
/// when the request gives the up axis.
void apply_anatomical_camera(const CameraRequest& r, const AnatomicalFrame& f, Camera& c, const CameraWarning& warn = {});

}  // namespace meshless
