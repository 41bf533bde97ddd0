// An axes triad and a scale bar drawn into a rendered picture (`--axes`): the orientation of the
// world's x, y, z axes (red, green, blue, the usual convention, labelled X, Y, Z) from a corner at
// the bottom left, as the camera sees them (an axis pointing at the viewer is short), and at the
// bottom centre a bar of a round world length (1, 2 or 5 x 10^k world units, about a fifth of the
// picture's width at the depth of the framed centre; exact there under perspective, everywhere
// orthographic), labelled with that length and the world's unit when known, in the built-in font
// (kernels/colorbar.hpp; units in lower case: mm, cm, um, nm, m).
// Layout: s = max(1, min(W, H) / 160); triad arms 12s + 4 pixels, from (14s + 6, H - 14s - 6); bar
// 2s thick, 8s + 4 pixels above the bottom edge. Pictures smaller than 48 x 48 pixels get nothing.
// Units: world units (the data's: millimetres for DICOM, NIfTI, NRRD space, as the file says).
// Pure, reentrant; throws nothing but std::bad_alloc. Dissertation: none (picture annotation).
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "kernels/camera.hpp"
#include "kernels/splat_rasterizer.hpp"

namespace meshless {

/// The scale bar's world length: the largest 1, 2 or 5 x 10^k not above `target` (> 0, finite);
/// 0 for a target that is not.
double scale_bar_length(double target);

/// Draws the triad and the scale bar for the view `v` (the picture's camera over its framed box);
/// the bar's label is its length followed by `unit` when given ("50 mm").
void draw_axes(Image& img, const ViewTransform& v, std::array<std::uint8_t, 3> ink = {255, 255, 255}, const std::string& unit = "");

}  // namespace meshless
