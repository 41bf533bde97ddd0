// The marching 3x3x3 stencils over a binning grid (dissertation section 5.4: "Points inside a given
// 3 x 3 x 3 stencil of binning grid cells are used to construct a local tetrahedrization. The
// stencils are centered in alternate cells to avoid excessive tetrahedrization overlap").
//
// Per axis with D cells (D >= 3), S = D / 2 stencils; stencil m is centred in cell
// c(m) = min(2m + 1, D - 2) and holds cells c - 1 .. c + 1, so consecutive stencils share one layer
// of cells (the last one, when D is even, shares two) and together they hold every cell.
// Ownership (which tetrahedra a stencil contours, so that neighbouring stencils do not all seed the
// same triangles): stencil m owns the interval [2m + 0.5, 2m + 2.5) of continuous cell coordinates
// (its centre cell widened by half a cell on each side), the first one from -infinity, the last one
// to +infinity: the owned boxes partition space, and each lies inside its stencil's cells. A
// stencil contours the tetrahedra of its Delaunay tetrahedrization whose bounding box meets its owned
// box; every point of the domain lies in one owned box, and is contoured when that stencil's
// tetrahedrization covers it: always inside the centre cell (one point in each of the 27 cells
// after regularisation puts a point of the stencil beyond every face of the centre cell), and in
// the half-cell margins wherever the surrounding points reach past them (tests/kernels: the cover
// of uniform, clustered and layered points). Tetrahedra that meet two owned boxes are contoured by
// both stencils (duplicate points, allowed: they project onto the same surface, section 4.6).
// Stencils are numbered s = sx + Sx (sy + Sy sz). Pure, constexpr-friendly, throws nothing.
#pragma once
#include <array>
#include <cstdint>
#include <limits>

namespace meshless {

/// Stencils along an axis of `cells` cells (>= 3).
constexpr std::int64_t stencil_count(std::int64_t cells) { return cells / 2; }

/// Centre cell of stencil m along an axis of `cells` cells.
constexpr std::int64_t stencil_centre(std::int64_t m, std::int64_t cells) { return 2 * m + 1 < cells - 2 ? 2 * m + 1 : cells - 2; }

/// Owned interval [lo, hi) of stencil m, in continuous cell coordinates.
inline std::array<double, 2> stencil_owned(std::int64_t m, std::int64_t cells) {
    const double inf = std::numeric_limits<double>::infinity();
    return {m == 0 ? -inf : 2.0 * double(m) + 0.5, m + 1 >= stencil_count(cells) ? inf : 2.0 * double(m) + 2.5};
}

struct StencilGrid {
    std::array<std::int64_t, 3> count{0, 0, 0};  ///< stencils per axis
    explicit StencilGrid(const std::array<std::int64_t, 3>& dims)
        : count{stencil_count(dims[0]), stencil_count(dims[1]), stencil_count(dims[2])} {}
    std::int64_t total() const { return count[0] * count[1] * count[2]; }
    std::array<std::int64_t, 3> coords(std::int64_t s) const { return {s % count[0], (s / count[0]) % count[1], s / (count[0] * count[1])}; }
};

}  // namespace meshless
