// Turntable camera and view transform for the software splat renderer (dissertation section 3.6:
// frame rates measured over 36 frames, rotating the model 10 degrees about the y axis each time).
//
// Conventions and units:
//  - World space: the records' coordinates. The camera orbits the centre of the bounding sphere of
//    the box [lo, hi]; azimuth rotates about the up axis (world +y by default; `up_axis` and
//    `up_negative` choose any of +-x, +-y, +-z, which then points up in the picture at elevation 0),
//    elevation tilts the camera above (positive) or below the plane normal to it. Angles in degrees; azimuth is reduced modulo 360,
//    so 0 and 360 give bit-identical transforms.
//  - Camera space: x right, y up, z towards the viewer; the eye sits at (0, 0, distance) and looks
//    down -z. depth = distance - z_camera (> 0 in front of the eye).
//  - Screen space: pixels, x to the right, y down, pixel (i, j) covers [i, i+1) x [j, j+1) and has
//    its centre at (i + 0.5, j + 0.5).
//  - Framing: at zoom 1 the bounding sphere of the box exactly fills the smaller image dimension
//    (perspective: the sphere's cone of sight has half angle fov/2; orthographic: the sphere's
//    radius maps to min(width, height) / 2 pixels), so the whole box is visible for any azimuth and
//    elevation. A degenerate or non-finite box is framed as a sphere of radius 1.
// Preconditions: width, height >= 1, 0 < fov_deg < 180, zoom > 0 (asserted).
// Throws nothing. Pure value types, thread-safe to share once built.
#pragma once
#include "kernels/vec3.hpp"

namespace meshless {

struct Camera {
    double azimuth_deg = 30;    ///< rotation about the world y axis
    double elevation_deg = 20;  ///< tilt above the horizontal plane
    double zoom = 1.0;          ///< magnification; 1 frames the bounding sphere exactly
    int width = 800, height = 800;
    bool perspective = true;
    double fov_deg = 30;  ///< full vertical/horizontal field of view of the smaller image side
    int up_axis = 1;            ///< 0 x, 1 y, 2 z: the world axis that points up
    bool up_negative = false;   ///< up is the negative direction of up_axis
};

/// The azimuth and elevation (degrees) of a camera with the given up axis that looks along the world
/// direction `dir` (need not be unit; nonzero): the named views (--view +x ... iso) in any up frame.
/// A view along the up axis gets elevation -+90 and azimuth 0.
void view_angles(const Vec3& dir, int up_axis, bool up_negative, double& azimuth_deg, double& elevation_deg);

struct ViewTransform {
    float rot[3][3] = {};  ///< world -> camera rotation; rows are the camera x, y, z axes in world space
    Vec3 centre;           ///< bounding-sphere centre (world)
    double radius = 1;     ///< bounding-sphere radius (world)
    double distance = 1;   ///< eye distance from the centre (world)
    double focal_px = 1;   ///< perspective: pixels per unit of x/depth; orthographic: pixels per world unit
    double near_depth = 0; ///< points with depth <= near_depth are not drawn
    double cx = 0, cy = 0; ///< image centre in pixels
    int width = 1, height = 1;
    bool perspective = true;

    /// Camera-space coordinates of a world point.
    Vec3 to_camera(const Vec3& p) const;
    /// Camera-space direction of a world direction (rotation only).
    Vec3 rotate(const Vec3& d) const;
    /// Screen position (pixels) and depth of a world point; false when depth <= near_depth.
    bool project(const Vec3& p, double& sx, double& sy, double& depth) const;
    /// Pixels per world unit at the given depth (the splat radius scale r_px = radius * this).
    double pixels_per_unit(double depth) const { return perspective ? focal_px / depth : focal_px; }
};

/// Builds the view of `cam` framing the box [lo, hi] (see the framing rule above).
ViewTransform make_view(const Camera& cam, const Vec3& lo, const Vec3& hi);

}  // namespace meshless
