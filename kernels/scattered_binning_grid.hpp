// The binning grid of scattered data (dissertation section 5.3, "Regularization"): the points are
// rescaled into the unit cube, an octree is refined over them, the binning level l_b is the median
// of the levels collected by the depth-first rule, and the 2^l_b grid is grown by one layer of
// cells on every side so that a single layer of cells surrounds the points' bounding box.
//
// Rescaling: per axis, u_a = (p_a - lo_a) / (hi_a - lo_a), so the data's bounding box is the unit
//   cube (anisotropic data, e.g. boreholes kilometres wide and metres deep, gets 2^l_b cells along
//   every axis). An axis whose extent is below `degenerate_axis` x the largest extent is degenerate
//   (all points on a plane or a line): the octree does not split it (a node has 2^d children, d the
//   non-degenerate axes), and the grid gives it one interior cell, centred on the points, of the
//   largest non-degenerate cell edge, plus the border layer (3 cells).
// Depth-first rule (5.3): from the root, a node with at least one empty child appends its level to
//   the list and is not descended; a leaf (at most one point) appends its level; a node whose
//   children are all non-empty is descended. l_b = the lower median of the list. Descending needs
//   2^d non-empty children, so the recursion depth is at most log_{2^d}(n) + 1 whatever the
//   distribution (duplicates and near-duplicates never all fill 2^d children); `max_depth` caps it
//   anyway (a node at max_depth appends its level). Only the nodes the rule visits are built: nodes
//   below them (the rest of the "refined until each leaf holds at most one point" octree) cannot
//   change the list, so they are never made; the MPU field builds its own octree.
// Grid: l = min(l_b, max_level); while the grid's cell count exceeds max_cells, l is lowered
//   (coarsened = true; the caller warns). Non-degenerate axis a: dims_a = 2^l + 2, cell edge
//   h_a = (hi_a - lo_a) / 2^l, origin_a = lo_a - h_a, so the points lie in cells 1 .. 2^l and cells 0
//   and dims_a - 1 are the surrounding layer. Degenerate axis: dims_a = 3.
// Binning: points are counted into cells (counting sort, stable: within a cell, input order), the
//   index every stencil reads its points from (kernels/stencil_regularisation.hpp).
// Units: world units for origin/cell; levels are octree depths (root = 0).
// Preconditions: positions finite. make_binning_grid throws InvalidArgument for an empty input, when
//   every point coincides, or when max_cells < 27 (not even one stencil). bin_points throws
//   InvalidArgument for more than 2^32 - 1 points. Pure and reentrant; allocates its results.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

struct BinningGridParams {
    int max_level = 10;                       ///< cap on l_b (1024 cells per axis)
    std::int64_t max_cells = 20'000'000;      ///< cap on the grid's cell count (coarsen below it)
    int max_depth = 30;                       ///< octree depth cap of the depth-first rule
    double degenerate_axis = 1e-9;            ///< relative extent below which an axis is degenerate
};

struct BinningGrid {
    Vec3 origin;                               ///< world position of cell (0,0,0)'s lower corner
    Vec3 cell{1, 1, 1};                        ///< cell edge lengths, world units
    std::array<std::int64_t, 3> dims{0, 0, 0};
    int level = 0;                             ///< l_b of the grid
    int rule_level = 0;                        ///< l_b the median rule asked for (> level when capped/coarsened)
    bool coarsened = false;                    ///< lowered below rule_level by max_level or max_cells
    std::array<bool, 3> degenerate{false, false, false};
    std::array<Vec3, 2> bounds{};              ///< the points' bounding box

    std::int64_t cell_count() const { return dims[0] * dims[1] * dims[2]; }
    std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + dims[0] * (j + dims[1] * k); }
    Vec3 cell_centre(std::int64_t i, std::int64_t j, std::int64_t k) const {
        return {origin.x + (double(i) + 0.5) * cell.x, origin.y + (double(j) + 0.5) * cell.y, origin.z + (double(k) + 0.5) * cell.z};
    }
    /// World diagonal of one cell.
    double diagonal() const { return norm(cell); }
    /// The cell of a data point (inside bounds), clamped to the interior cells [1, dims - 2].
    std::array<std::int64_t, 3> cell_of(const Vec3& p) const;
    /// Continuous cell coordinates (p - origin) / cell per axis.
    Vec3 to_cell_coords(const Vec3& p) const {
        return {(p.x - origin.x) / cell.x, (p.y - origin.y) / cell.y, (p.z - origin.z) / cell.z};
    }
};

/// The levels the depth-first rule collects over `unit` positions (each coordinate in [0, 1]),
/// splitting only the axes with split[a] true; in traversal order (children in order x, y, z bits).
std::vector<int> binning_rule_levels(std::span<const Vec3> unit, std::array<bool, 3> split, int max_depth);

/// The lower median of `levels` (0 for an empty list).
int median_level(std::vector<int> levels);

/// The binning grid of `pos` (see above).
BinningGrid make_binning_grid(std::span<const Vec3> pos, const BinningGridParams& params = {});

/// The grid of points with bounding box `bounds` for which the depth-first rule asked for
/// `rule_level` (make_binning_grid's last step; kernels/binning_rule_scan.hpp finds the level
/// without holding the points).
BinningGrid binning_grid_of(const std::array<Vec3, 2>& bounds, int rule_level, const BinningGridParams& params = {});
/// The axes the rule's octree splits: those whose extent is above degenerate_axis x the largest.
std::array<bool, 3> binning_split_axes(const std::array<Vec3, 2>& bounds, const BinningGridParams& params);
/// p rescaled into the unit cube of `bounds` (0 along an unsplit axis), as the rule sees it.
Vec3 binning_unit_position(const Vec3& p, const std::array<Vec3, 2>& bounds, const std::array<bool, 3>& split);
/// make_binning_grid's refusals for n points with bounding box `bounds` (InvalidArgument).
void check_binning_input(std::uint64_t n, const std::array<Vec3, 2>& bounds, const BinningGridParams& params);

/// Points counted into the cells of a grid: the points of cell c are order[start[c] .. start[c+1]).
struct BinnedPoints {
    std::vector<std::uint32_t> start;  ///< size cell_count() + 1
    std::vector<std::uint32_t> order;  ///< point indices, size n
    std::int64_t empty_cells = 0;      ///< cells without a point (border layer included)
    std::int64_t empty_interior_cells = 0;  ///< of those, cells not in the surrounding layer
    std::uint32_t max_per_cell = 0;
    std::span<const std::uint32_t> points_of(std::int64_t c) const {
        return {order.data() + start[static_cast<std::size_t>(c)], order.data() + start[static_cast<std::size_t>(c) + 1]};
    }
};

BinnedPoints bin_points(const BinningGrid& g, std::span<const Vec3> pos);

}  // namespace meshless
