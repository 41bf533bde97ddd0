// The camera of the Python module's pictures (meshless.render, meshless.splat; python/README.md),
// from the keyword options the commands take as --size, --azimuth, --elevation, --up, --view, --zoom
// and --ortho, with their meanings and defaults: a camera orbiting the frame's centre (kernels/camera.hpp),
// degrees about the up axis and above the plane normal to it; a volume whose header gives the
// patient's axes is drawn head up, face to the viewer (kernels/anatomical_view.hpp) unless `up` is given.
// Units: pixels (size), degrees (azimuth, elevation), a factor (zoom).
// Throws ValueError (pybind11::value_error) for an option out of its domain.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "formats/anatomical_frame.hpp"
#include "kernels/camera.hpp"

namespace meshless::python {

/// The options as given (nullopt: not given, the command's default).
struct CameraOptions {
    int width = 512, height = 512;       ///< 1..16384 each
    std::optional<double> azimuth, elevation;
    std::optional<std::string> up;       ///< "x", "y", "z", "-x", "-y", "-z"
    std::optional<std::string> view;     ///< "+x" ... "-z", "iso"
    double zoom = 1;
    bool ortho = false;
};

/// The camera the options describe (checked); `warnings` receives what the command prints to stderr.
Camera camera_of(const CameraOptions& o, std::vector<std::string>* warnings = nullptr);

/// The command's default for data whose header gives the patient's axes: head up, face to the
/// viewer, turned by the azimuth and elevation; nothing when `up` was given.
void apply_anatomical(const CameraOptions& o, const AnatomicalFrame& f, Camera& c, std::vector<std::string>* warnings = nullptr);

}  // namespace meshless::python
