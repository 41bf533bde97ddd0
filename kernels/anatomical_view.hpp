// The default camera of a volume whose header gives the patient's axes (formats/anatomical_frame.hpp):
// head up, face towards the viewer, turned as the generic default is. With `lps` the LPS unit
// direction of world +x, +y, +z:
//   up    = the world axis (and sign) closest to superior (LPS +z);
//   front = of the other two axes, the one (and sign) closest to anterior (LPS -y): the camera sits
//           on that side and looks toward posterior (azimuth 0 of that frame);
//   then turned by azimuth and elevation, +30 and +20 degrees by default, as the generic default
//   (y up, azimuth 30, elevation 20 from the +z side) is turned from its own front (the CLI passes
//   --azimuth/--elevation here, so they turn the face-on view).
// VTK's Medical examples look at the headsq CT this way (view up -z, camera on -y, then azimuth 30,
// elevation 30). Throws nothing; pure.
// Dissertation: none (presentation).
#pragma once
#include <array>

#include "kernels/camera.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct AnatomicalView {
    int up_axis = 1;
    bool up_negative = false;
    int front_axis = 2;          ///< the world axis toward the patient's front (anterior)
    bool front_negative = false; ///< anterior is its negative direction
    double azimuth_deg = 30, elevation_deg = 20;
};

AnatomicalView anatomical_view(const std::array<Vec3, 3>& lps, double turn_azimuth_deg = 30, double turn_elevation_deg = 20);
/// Sets the camera's up axis, azimuth and elevation to the view (size, zoom, projection kept).
void apply_view(const AnatomicalView& v, Camera& c);

}  // namespace meshless
