// Point generation of iso-splatting, paradigm (C) (dissertation sections 3.4-3.5): one sample per
// active cell, at the cell centre, with value and gradient by trilinear interpolation, and the cell's
// corner values so that either projection (Eq. 3.5 or Eq. 3.3) can run downstream.
//
// A cell is active for isovalue f_I when its corners are not all on one side: some corner >= f_I
// and some corner < f_I (the marching-cubes case is neither 0 nor 255). A NaN corner reads as
// "below" in that test; cells that look active and have a NaN or Inf corner are skipped and counted
// (nonfinite_cells). Cells whose finite corners all lie on one side are inactive whatever their
// other corners hold, so they are not counted (marching cubes counts every cell touching a bad
// sample, hence its larger count). Units: world positions (grid origin + spacing), gradient in value
// units per world unit, radius = radius_scale * 1/2 * sqrt(sx^2+sy^2+sz^2) world units.
// Cells are addressed by "cell rows": row r = j + (ny-1)*k holds the nx-1 cells (i, j, k).
// Pure and reentrant; concurrent calls on disjoint row ranges are safe.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "kernels/grid.hpp"
#include "kernels/project_sample.hpp"
#include "kernels/records.hpp"

namespace meshless {

struct SamplingParams {
    double radius_scale = 1.0;  ///< splat radius as a multiple of half the cell diagonal
    /// Index of the view's voxel (0,0,0) in the whole volume, for views of a part (a brick) whose
    /// grid origin is the whole volume's origin: positions are origin + (offset + i) * spacing, the
    /// very same arithmetic as for the whole volume, so bricked and in-memory runs agree bit for bit.
    std::array<std::int64_t, 3> index_offset{0, 0, 0};
};

struct SamplingStats {
    std::int64_t active_cells = 0;      ///< samples emitted
    std::int64_t nonfinite_cells = 0;   ///< cells skipped because a corner is NaN/Inf
    SamplingStats& operator+=(const SamplingStats& o) {
        active_cells += o.active_cells;
        nonfinite_cells += o.nonfinite_cells;
        return *this;
    }
};

/// Number of cell rows of the grid: (ny-1)*(nz-1), 0 when any dimension is < 2.
std::int64_t cell_row_count(const GridSpec& g);

/// Appends one SampleRecord per active cell in cell rows [row0, row1), in row-major order
/// (i fastest). Preconditions: 0 <= row0 <= row1 <= cell_row_count(v.grid).
void sample_active_cells(const VolumeView& v, double iso, std::int64_t row0, std::int64_t row1,
                         const SamplingParams& params, std::vector<SampleRecord>& out,
                         SamplingStats& stats);

/// A cell's low corner and centre on one axis as the samples' floats: lo = origin + i * spacing in
/// double (i the whole-volume index), cell_lo = float(lo), centre = float(lo + 0.5 * spacing): the
/// arithmetic of sample_active_cells and complete_centre_samples (the encoder of cell-indexed
/// frames checks records against it).
struct CellAxis {
    float lo, centre;
};
inline CellAxis cell_axis(double origin, double spacing, std::uint32_t i) {
    const double lo = origin + static_cast<double>(i) * spacing;
    return {static_cast<float>(lo), static_cast<float>(lo + 0.5 * spacing)};
}

/// Completes records from their cells (the decoder of cell-indexed sample frames, formats/
/// sample_cell_frame.hpp): for each r < n, with rec[r].corner[] set and (i, j, k) = ijk[3r..3r+2]
/// its cell's indices in the whole volume (SamplingParams::index_offset included) on the grid
/// (origin, spacing), sets pos, grad, value, cell_lo and cell_size exactly as sample_active_cells
/// sets them from the volume's values; radius is left as it is. The bytes equal the generator's
/// whenever the corner floats hold the volume's values exactly, as they always do for the sample
/// types there are (uint8, int16, uint16, float32). Pure.
void complete_centre_samples(const double origin[3], const double spacing[3], const std::uint32_t* ijk,
                             SampleRecord* rec, std::size_t n);

/// complete_centre_samples for cells whose corners are uint8 values (corners[8r..8r+7] for record
/// r, index dx + 2 dy + 4 dz): the same bytes, corner[] included, computed in integers. With such
/// corners every intermediate of the trilinear interpolation at the centre is exact, so the value is
/// (sum of corners) / 8 and the local gradient (an integer in [-1020, 1020]) / 4 on each axis; the
/// world gradient's rounding, (L / 4) / spacing, is looked up in `table` (filled for the spacing
/// when it was made for another spacing, compared bit for bit). Pure apart from the table.
struct CentreGradientTable {
    double spacing[3] = {0, 0, 0};
    std::vector<float> grad;  ///< 3 x 2041: axis a, local gradient L/4 for L in [-1020, 1020]
};
void complete_centre_samples_u8(const double origin[3], const double spacing[3], const std::uint32_t* ijk,
                                const std::uint8_t* corners, SampleRecord* rec, std::size_t n,
                                CentreGradientTable& table);

/// The same samples, each projected at once by project_sample (no SampleRecord is stored): the
/// in-process fast path of paradigm (C). Output bytes equal sample_active_cells followed by
/// project_sample on each record: for `exact` and `none` the same record is built and projected;
/// `approx` runs its own two-cells-per-step SSE2 code with the same operations in the same order
/// (checked byte for byte by tests/kernels/test_cell_sampling.cpp).
void sample_and_project_active_cells(const VolumeView& v, double iso, std::int64_t row0, std::int64_t row1,
                                     const SamplingParams& params, Projection mode,
                                     std::vector<PointRecord>& out, SamplingStats& stats,
                                     ProjectionStats& pstats);

}  // namespace meshless
