// The marching stencil of the scattered-data isosurface (dissertation sections 5.4-5.6): for each
// 3x3x3 stencil of a range of one stencil row (kernels/marching_stencils.hpp), its points — the
// data points binned in its 27 cells (kernels/scattered_binning_grid.hpp), plus one regularisation
// point at the centre of each empty cell with the field's value there
// (kernels/stencil_regularisation.hpp) — are tetrahedralised (kernels/stencil_delaunay.hpp, CGAL,
// exact predicates), every tetrahedron the stencil owns is contoured at the isovalue by marching
// tetrahedra (kernels/marching_tetrahedra.hpp; vertex values: data values, field values for
// regularisation points), and inside each triangle the barycentric lattice of n(n+1)/2 samples
// (kernels/barycentric_lattice.hpp) gives one SeedRecord each, for the Newton projection onto the
// field (stream/field_project_stage.hpp), exactly as the multiblock seeds (section 4.4).
//
// Seed fields: position (world), the triangle's unit normal (wound towards decreasing values by
// marching tetrahedra, VTK's convention), value = iso, base_radius = sqrt(2A / (pi n (n+1))) for the triangle's world
// area A, cell_diagonal = the stencil's local scale l = min(the binning cell's world diagonal,
// twice the median edge length of the stencil's tetrahedrization) (the Newton tolerance and travel
// limit are relative to it: section 4.4's cell diagonal; the median edge keeps them at the data's
// spacing where the binning grid is coarse for the distribution, e.g. far-apart clusters, section
// 5.8, so seeds of tetrahedra spanning empty space are dropped rather than accepted where they lie),
// block = 0.
// A stencil whose point values (data and regularisation, NaN ignored) are all >= iso or all < iso
// is not tetrahedralised (no tetrahedron of it can be crossed). Delaunay failures (too few distinct
// points, all coplanar, a CGAL exception) are counted and the stencil skipped. The tetrahedrization
// is computed in stencil-local cell coordinates (world offsets and anisotropic cells out of the
// arithmetic) and mapped back to world per axis (an affine map with positive scales: crossings and
// orientations are preserved).
// Order: stencils in index order, then tetrahedra in the triangulation's order, then triangles, then
// lattice order: deterministic for a given input, whatever thread runs it.
// Units: world positions, the data's values. Pure apart from the Field call; reentrant.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/field.hpp"
#include "kernels/point_coverage.hpp"
#include "kernels/records.hpp"
#include "kernels/scattered_binning_grid.hpp"

namespace meshless {

struct StencilSeedStats {
    std::int64_t stencils = 0;              ///< stencils visited
    std::int64_t crossed_stencils = 0;      ///< stencils whose values straddle iso (tetrahedralised)
    std::int64_t regularisation_points = 0; ///< field evaluations at empty cell centres (with repeats across rows)
    std::int64_t uncovered_regularisation = 0;  ///< of those, NaN because the data does not cover them
    std::int64_t delaunay_failures = 0;     ///< crossed stencils skipped: flat, too few points or CGAL failure
    std::int64_t tets = 0;                  ///< tetrahedra of the crossed stencils
    std::int64_t owned_tets = 0;            ///< of those, the ones the stencils own (contoured)
    std::int64_t nonfinite_tets = 0;        ///< owned tetrahedra skipped for a non-finite vertex value
    std::int64_t triangles = 0;             ///< triangles with a positive area
    std::int64_t zero_area_triangles = 0;   ///< triangles skipped for a zero area
    std::int64_t seeds = 0;                 ///< seeds written
    std::int64_t max_stencil_points = 0;    ///< largest point count of one tetrahedralised stencil
    std::int64_t regularisation_ns = 0;     ///< time in regularise_block
    std::int64_t delaunay_ns = 0;           ///< time in stencil_delaunay
    static constexpr int kCounters = 14;
    static constexpr int kMaxIndex = 10;  ///< as_array index of max_stencil_points (a maximum, not a sum)
    std::array<std::int64_t, kCounters> as_array() const {
        return {stencils, crossed_stencils, regularisation_points, delaunay_failures, tets, owned_tets, nonfinite_tets,
                triangles, zero_area_triangles, seeds, max_stencil_points, regularisation_ns, delaunay_ns, uncovered_regularisation};
    }
    static StencilSeedStats from_array(const std::array<std::int64_t, kCounters>& v) {
        StencilSeedStats s{v[0], v[1], v[2], 0, v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10], v[11], v[12]};
        s.uncovered_regularisation = v[13];
        return s;
    }
};

/// What every stencil reads: the grid, the binned data points and their values, the field.
struct StencilInput {
    const BinningGrid& grid;
    const BinnedPoints& bins;
    std::span<const Vec3> pos;
    std::span<const double> value;
    const Field& field;
    /// Optional: regularisation points the data does not cover get NaN (kernels/stencil_regularisation.hpp).
    const PointCoverage* coverage = nullptr;
};

/// Seeds of stencils [s0, s1) (linear stencil indices of one row: same sy and sz), appended to `out`;
/// counts added to `st`. `lattice` = barycentric_lattice(n). Throws only std::bad_alloc.
void stencil_seeds(const StencilInput& in, double iso, int n, std::span<const std::array<double, 3>> lattice, std::int64_t s0,
                   std::int64_t s1, std::vector<SeedRecord>& out, StencilSeedStats& st);

/// The stencil's tetrahedra that it owns, in world coordinates (for tests of the domain cover):
/// stencil s's points (regularisation values from the field) tetrahedralised; returns false when
/// the Delaunay failed. Vertex values in `values` (4 per tetrahedron).
bool stencil_owned_tets(const StencilInput& in, std::int64_t s, std::vector<std::array<Vec3, 4>>& tets,
                        std::vector<std::array<double, 4>>* values = nullptr);

}  // namespace meshless
