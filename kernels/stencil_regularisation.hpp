// Regularisation of the binning grid, on the fly (dissertation sections 5.3-5.4: "Empty cells are
// filled with a single data point at the center of the cell whose function value is determined by
// interpolating ... These additional points are used for creating local tetrahedrizations and are
// not considered when evaluating the approximation"; section 5.7's remedy for HighResHead's
// five-fold growth: "the generation of samples in the empty cells on-the-fly").
//
// regularise_block gives, for a box of binning cells [lo, hi] (inclusive cell indices), the field's
// value at the centre of every empty cell of the box, in one Field::evaluate call; nothing is stored
// beyond the box (a stencil row's 3 x 3 x (cells of the row) block, stream/stencil_seed_stage.hpp),
// and these points never enter the field. Cells that hold data points get NaN (unused). The field
// may give NaN where it has no support (e.g. far from the data); the tetrahedra with such a vertex
// are skipped by marching tetrahedra and counted by the caller. With a coverage (kernels/point_coverage.hpp),
// a centre the data does not cover gets NaN too (counted in `uncovered`): the fields extrapolate
// into empty space, and a regularisation value there would put a surface where no data is (e.g.
// between far-apart clusters, where the binning grid is necessarily coarse, section 5.8).
// Units: world positions, the data's values. Preconditions: 0 <= lo <= hi < dims per axis.
// Pure apart from the Field call (thread-safe, kernels/field.hpp); allocates in `out`.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "kernels/field.hpp"
#include "kernels/point_coverage.hpp"
#include "kernels/scattered_binning_grid.hpp"

namespace meshless {

struct RegularisedBlock {
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{-1, -1, -1};
    std::vector<double> value;   ///< per cell of the box, x fastest; NaN for cells with data
    std::int64_t evaluations = 0;  ///< empty cells of the box (regularisation points made)
    std::int64_t uncovered = 0;    ///< of those, centres the coverage marked NaN
    double at(std::int64_t i, std::int64_t j, std::int64_t k) const {
        const std::int64_t nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1;
        return value[static_cast<std::size_t>((i - lo[0]) + nx * ((j - lo[1]) + ny * (k - lo[2])))];
    }
};

void regularise_block(const BinningGrid& g, const BinnedPoints& bins, const Field& f, const std::array<std::int64_t, 3>& lo,
                      const std::array<std::int64_t, 3>& hi, RegularisedBlock& out, const PointCoverage* coverage = nullptr);

}  // namespace meshless
