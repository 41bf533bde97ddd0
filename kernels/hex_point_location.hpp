// Point location in the cells of a structured block (curvilinear or not): is a world point inside
// one of the block's hexahedral cells (the trilinear image of the unit cube)? Used by the naive
// multiblock statistics (kernels/crack_edges.hpp) to tell a crack (a surface boundary inside the
// data) from the outer boundary of the data (dissertation section 4.2).
//
// Cells considered: those whose 8 corners are valid and finite (StructuredBlock::valid), whatever
// their Jacobian. A point is inside cell C when the inverse trilinear map (Newton from the cell
// centre, at most 24 steps, converged when the step is below 1e-10 in parametric units) gives
// (u, v, w) with every coordinate in [-tol, 1 + tol]; tol (parametric units, default 1e-3) absorbs
// the float rounding of mesh vertices and the mismatch of the bilinear faces of blocks that meet.
// Candidates come from a uniform bin grid over the block's bounding box (about one bin per cell;
// each cell in every bin its bounding box, grown by tol of its extent, overlaps).
// Memory: O(cells indexed). Construction O(cells); a query O(cells per bin). A region (the box of
// the points to be located) restricts the index to the cells near it. Throws std::bad_alloc.
// Thread-safety: const members are thread-safe; the block must outlive the locator.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "kernels/structured_block.hpp"

namespace meshless {

class BlockCellLocator {
public:
    explicit BlockCellLocator(const StructuredBlock& b, double tol = 1e-3);
    /// Only the cells whose (grown) bounding box meets the box [region_lo, region_hi] are indexed:
    /// contains() is exact for points inside the region (and may miss cells outside it).
    BlockCellLocator(const StructuredBlock& b, double tol, const Vec3& region_lo, const Vec3& region_hi);
    /// True when p lies in a valid cell (within tol).
    bool contains(const Vec3& p) const;
    /// Inverse trilinear map of cell (i,j,k) at p; false when Newton does not converge.
    bool cell_coordinates(std::int64_t i, std::int64_t j, std::int64_t k, const Vec3& p, Vec3& uvw) const;
    std::int64_t valid_cells() const { return static_cast<std::int64_t>(cells_.size()); }

private:
    const StructuredBlock& b_;
    double tol_;
    Vec3 lo_, hi_;
    std::array<std::int64_t, 3> bins_{0, 0, 0};
    Vec3 bin_size_;
    std::vector<std::int64_t> cells_;            // linear cell index i + (ni-1)(j + (nj-1) k) of valid cells
    std::vector<std::uint32_t> offset_, items_;  // CSR: bin -> indices into cells_
    std::int64_t bin_of(double x, int axis) const;
    void build(const Vec3* region_lo, const Vec3* region_hi);
};

}  // namespace meshless
