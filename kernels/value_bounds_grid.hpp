// Value bounds over macro cells: the empty-space skipping structure of the ray caster
// (kernels/ray_caster.hpp; dissertation section 6.6 renders LOD fields, section 7.4 asks for
// volume rendering of scattered data). A regular grid of boxes over a field's domain, each with an
// interval [vmin, vmax] that holds (or, for scattered data, is meant to hold) every value the field
// takes inside the box. A ray skips a box whose interval the transfer function maps to opacity 0.
//
// Sources, and how conservative they are:
//  - a regular volume (value_bounds_from_blocks): the min/max of the voxels of blocks of B cells
//    (kernels/block_minmax.hpp). The trilinear interpolant never leaves the range of a cell's
//    corners, so these bounds are exact: skipping cannot change a volume rendering.
//  - a brick store: the bricks' vmin/vmax from its index (built in ooc/brick_field.hpp), likewise exact.
//  - scattered points (value_bounds_from_points): the min/max of the data values of the points
//    within `pad` of the box (pad: the reach of the field's local fits, a few point spacings),
//    widened by `margin` on each side. Meshless interpolants (multiquadrics blended by partition of
//    unity) may overshoot their data, so these bounds are a documented heuristic, not a proof: the
//    tests compare pictures rendered with and without skipping. A box with no point within pad
//    gets the empty interval (vmin = +inf > vmax = -inf): the data does not reach it, the field there
//    is extrapolation (the role of --max-gap's NaN in probe/slice), and the ray caster treats it as
//    empty space. For a box-filling point set no box is empty; for curvilinear grids (PLOT3D) and
//    clouds with holes this keeps the extrapolated shell out of the picture.
// Units: world coordinates, the data's values. Thread-safety: plain data; builders are reentrant.
// Throws InvalidArgument for a non-positive cell edge or a grid of more than 2^27 boxes.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/block_minmax.hpp"
#include "kernels/grid.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct ValueBoundsGrid {
    Vec3 origin;                                ///< low corner of box (0, 0, 0)
    Vec3 cell{1, 1, 1};                         ///< box edge lengths (world), > 0
    std::array<std::int64_t, 3> dims{0, 0, 0};  ///< boxes per axis
    /// per box, x fastest; NaN: unknown (never skipped); vmin > vmax: no data (always skipped)
    std::vector<double> vmin, vmax;

    std::int64_t count() const { return dims[0] * dims[1] * dims[2]; }
    std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + dims[0] * (j + dims[1] * k); }
};

/// The blocks of a regular volume's min/max summary as boxes: block b covers the voxels
/// [b*B, min(b*B + B, n - 1)] (world: origin + index * spacing).
ValueBoundsGrid value_bounds_from_blocks(const BlockMinMax& blocks, const GridSpec& grid);

/// Boxes of edge `cell_edge` (world units, > 0) over `box`, each bounded by the values of the points
/// within `pad` (>= 0) of it, widened by `margin` (>= 0, data units) on each side.
ValueBoundsGrid value_bounds_from_points(std::span<const Vec3> pos, std::span<const double> value,
                                         const std::array<Vec3, 2>& box, double cell_edge, double pad, double margin);

/// The same in pieces, for points that come in parts (a point store's bricks): the empty boxes
/// (every interval empty; InvalidArgument as above), the points added (any order, any parts), the
/// margin once the last has been.
ValueBoundsGrid empty_point_bounds(const std::array<Vec3, 2>& box, double cell_edge);
void add_point_bounds(ValueBoundsGrid& grid, std::span<const Vec3> pos, std::span<const double> value, double pad);
void widen_point_bounds(ValueBoundsGrid& grid, double margin);

}  // namespace meshless
