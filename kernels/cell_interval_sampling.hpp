// Point generation for paradigm (A), "partial evaluation" (dissertation section 3.5, Table 3.1):
// once, for every isovalue at the same time, one sample per NON-CONSTANT cell, with what the
// approximate projection (Eq. 3.5) needs: location, function value, gradient, and the value interval
// [vmin, vmax] spanned by the cell's eight corners. A later extraction keeps the samples whose cell is
// active for its isovalue (vmin < f_I <= vmax, the convention of kernels/cell_sampling.hpp) and needs
// no volume.
//
// The sample of cell (i,j,k) is bit-identical to the pos/grad/value that sample_active_cells
// (paradigm C) computes for that cell: cell centre origin + (i + 1/2) * spacing in world units, the
// trilinear value and gradient there (value units per world unit), all in double, then rounded to
// float. Cells with a NaN/Inf corner are skipped and counted (paradigm C skips them too); constant
// cells (vmin == vmax) are never active for any isovalue and are skipped and counted.
//
// A call samples a box of cells of a view whose first voxel is voxel `first_voxel` of the whole
// volume (a brick of ooc/brick_store.hpp, or the whole volume with first_voxel = 0): the world
// position of a cell uses the global index first_voxel + local index and the whole volume's
// `origin`, so a brick gives the same bytes as the whole volume. The spacing is the view's.
// Order of the output: z, then y, then x slowest to fastest (row-major in the box).
// Pure and reentrant; no I/O. Preconditions: 0 <= lo <= hi <= view dims - 1 on each axis.
#pragma once
#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "kernels/grid.hpp"

namespace meshless {

/// The 36-byte stored sample of paradigm (A) (little endian, trivially copyable).
struct CellIntervalSample {
    float pos[3];   ///< cell centre, world units
    float grad[3];  ///< gradient of the trilinear interpolant at pos, value units / world unit
    float value;    ///< trilinear value at pos
    float vmin;     ///< smallest of the cell's 8 corner values (exact: corners are floats or integers)
    float vmax;     ///< largest of the cell's 8 corner values
};
static_assert(sizeof(CellIntervalSample) == 36 && std::is_trivially_copyable_v<CellIntervalSample>);

/// A box of cells [lo, hi) in a view's local cell indices.
struct CellBox {
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{0, 0, 0};
    std::int64_t count() const {
        std::int64_t n = 1;
        for (int a = 0; a < 3; ++a) n *= hi[a] > lo[a] ? hi[a] - lo[a] : 0;
        return n;
    }
};

/// All cells of a grid (empty when a dimension is < 2).
CellBox all_cells(const GridSpec& g);

struct CellIntervalStats {
    std::int64_t samples = 0;          ///< samples emitted (non-constant finite cells)
    std::int64_t constant_cells = 0;   ///< skipped: vmin == vmax
    std::int64_t nonfinite_cells = 0;  ///< skipped: a NaN/Inf corner
    CellIntervalStats& operator+=(const CellIntervalStats& o) {
        samples += o.samples;
        constant_cells += o.constant_cells;
        nonfinite_cells += o.nonfinite_cells;
        return *this;
    }
};

/// Appends one CellIntervalSample per non-constant finite cell of `box` (cells of v), see above.
void sample_cell_intervals(const VolumeView& v, const CellBox& box, const std::array<std::int64_t, 3>& first_voxel,
                           const std::array<double, 3>& origin, std::vector<CellIntervalSample>& out,
                           CellIntervalStats& stats);

/// The isovalue as the active-cell test sees it, for a volume of sample type t: a cell is active
/// for iso exactly when vmin < active_threshold(t, iso) <= vmax, which is the classification of
/// kernels/cell_sampling.hpp (some corner >= iso, some corner < iso, compared in the native type).
/// Integers: ceil(iso); float32: the smallest float >= iso (IsoThreshold<float>).
double active_threshold(SampleType t, double iso);

}  // namespace meshless
