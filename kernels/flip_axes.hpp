// Reversing a volume's samples along chosen axes: how readers honour a negative spacing (sample i at
// origin + i*s with s < 0 is the same field as the reversed samples at origin + (n-1)*s + i*|s|).
//
// In place, any sample type, O(voxels), no allocation beyond one row. Thread-safety: none needed
// (one volume, one caller). Dissertation: none (input plumbing for chapter 3).
#pragma once
#include <array>

#include "kernels/grid.hpp"

namespace meshless {

/// Reverses v's samples along every axis a with flip[a]; the grid is left as it is (the caller
/// has already set the origin and the positive spacing of the flipped axes).
void flip_axes(Volume& v, const std::array<bool, 3>& flip);

/// For a reader: sets g.spacing[axis] = |s|; when s < 0, moves g.origin[axis] to the position of
/// the last sample (origin + (dims-1)*s) and marks the axis in `flip` (apply flip_axes to the
/// samples). g.dims[axis] and g.origin[axis] must already hold the file's values.
void honour_signed_spacing(GridSpec& g, std::array<bool, 3>& flip, int axis, double s);

}  // namespace meshless
