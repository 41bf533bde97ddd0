// The sample recipe, what `meshless sample` runs (and any other front end): scattered points from a
// volume, uniform random positions in its bounds with values by trilinear interpolation
// (dissertation Eq. 3.1), as the paper made its scattered buckyball set (chapter 4). Deterministic
// for a seed (its own generator and conversion, kernels/splitmix.hpp; no std distributions).
// Positions falling in cells with a NaN corner are redrawn and counted.
// Units: world coordinates.
// Throws FormatError naming `name` when NaN/Inf cells leave too few finite positions (more than
// 20 draws a point).
#pragma once
#include <cstdint>
#include <string>

#include "kernels/grid.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

struct VolumeSample {
    PointSet points;           ///< value name "value", one block "sample"
    std::uint64_t redrawn = 0;  ///< positions in cells with NaN/Inf corners, drawn again
};

/// `count` (>= 1) points of `v` drawn with `seed`; `name` (the volume's file) names it in errors.
VolumeSample sample_volume(const Volume& v, std::uint64_t count, std::uint64_t seed, const std::string& name);

}  // namespace meshless
