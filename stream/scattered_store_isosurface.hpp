// The scattered-data isosurface (dissertation chapter 5, stream/scattered_isosurface.hpp) of a point
// store (.mlc, formats/point_store.hpp) within a memory budget: the field and the stencils run slab
// by slab (docs/architecture.md, "Fields out of core").
//
// Plan (plan_scattered_store): scans of the store, brick by brick, give what the whole set decides
// — its frame (bounding box, count, flatness: kernels/field_region.hpp), the binning grid (the
// depth-first rule one scan per level it descends: kernels/binning_rule_scan.hpp) and the points
// of every cell of that grid (the layer counts that size the slabs, the statistics and warnings of
// the in-memory path). Memory: 4 bytes a grid cell while planning, the rule's descended nodes.
// Run (run_scattered_store_isosurface): the stencil layers along z are cut into slabs that fit the
// budget. A slab's stencils, their seeds and every point Newton may reach (the max travel, plus one
// cell diagonal) make its query box; the store's points within a halo around it are loaded (the
// points in that z range of the bricks meeting it; the first halo is two MPU fit spheres at the
// mean density), binned on the whole grid, and get the support test and an MPU field built over
// that region in the whole set's frame (kernels/mpu_field.hpp, FieldRegion, with the bricks' and the
// grid cells' counts as the upper bound of the points not loaded). When a decision or list of the
// field read a ball that may lack points (MpuField::lacking_balls), the bricks that ball meets are
// loaded whole and the field built again (the first build stops before its fits); when the support
// test reached past the loaded range (PointCoverage::part_exact) the halo is doubled. The slab's
// stencils then run the in-memory graph (stencils -> seeds -> Newton) into a buffer whose batches go
// on to the sink in order. The stencils run in the in-memory order (z-major rows), so the output
// has the bytes of run_scattered_isosurface over the whole store read into memory, for any budget
// and thread count. The rebuilds and the widest halo are reported (ScatteredStoreReport).
// Memory: slabs are sized at bytes_per_point (1.2 KiB) a loaded point until a field has been built,
// then at what the fields so far took a point (+10 %) plus other_bytes_per_point; every build checks
// its octree's field against what the budget leaves (FieldRegion::max_field_bytes) before the fits and
// takes fewer layers when it does not fit; 8 bytes a grid cell; the kept fits (MpuFitCache).
// Throws InvalidArgument when the budget cannot hold the field of one stencil layer and its halo
// (the message says how much would), when the field is not mpu or the max travel is unlimited; FormatError and
// IoError from the store (naming the file and the brick); what the stages and the sink throw.
#pragma once
#include <array>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "formats/point_store.hpp"
#include "kernels/field_params.hpp"
#include "kernels/field_region.hpp"
#include "kernels/scattered_binning_grid.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/scattered_isosurface.hpp"

namespace meshless {

/// What the whole store decides (see above).
struct ScatteredStorePlan {
    std::string source;                ///< the name the metadata records
    FieldFrame frame;                  ///< bounds, count, flatness of every point
    std::array<double, 2> value_range{0, 0};
    std::uint64_t dropped_nonfinite = 0;  ///< dropped at conversion
    BinningGrid grid;
    std::vector<std::uint64_t> layer_points;  ///< points per cell layer along z (grid.dims[2] of them)
    /// Summed-area table of the points per grid cell ((dims + 1) per axis, 4 bytes each): how many
    /// points a box of cells holds, without reading them (the slabs' FieldRegion::missing).
    std::vector<std::uint32_t> cell_table;
    /// The points in cells [lo, hi] (inclusive, clamped to the grid).
    std::uint64_t points_in_cells(std::array<std::int64_t, 3> lo, std::array<std::int64_t, 3> hi) const;
    /// An upper bound on the points in the ball (c, r) outside the z range `loaded_z` (world): those
    /// of the cells meeting the ball in layers not wholly inside that range.
    std::uint64_t points_near(const Vec3& c, double r, const std::array<double, 2>& loaded_z) const;
    /// A lower bound on the points in the ball (c, r): those of the cells wholly inside it.
    std::uint64_t points_surely_in(const Vec3& c, double r) const;
    std::int64_t empty_cells = 0, empty_interior_cells = 0, largest_stencil = 0;
    std::uint32_t max_per_cell = 0;
    int scans = 0;                     ///< passes over the store
    double seconds = 0;
    bool crosses(double iso) const { return iso >= value_range[0] && iso <= value_range[1]; }
};

/// Scans `store` (see above); warn (may be empty) as bin_scattered_points warns. Throws
/// FormatError when the store holds fewer than 4 points, or all in one place.
ScatteredStorePlan plan_scattered_store(const PointStore& store, const std::string& source, const BinningGridParams& bp,
                                        const InputWarning& warn);

/// The plan of work that needs no stencils (the field queries and the rendering of a store): the
/// frame and values, and a grid of `level` (2^level cells a side of the bounding box, 0..10) for the
/// slabs' counts instead of the binning rule's: two scans of the store.
ScatteredStorePlan plan_store_field(const PointStore& store, const std::string& source, int level);

/// The metadata scattered_isosurface_meta writes for the same points in memory.
StreamMeta scattered_store_meta(const ScatteredStorePlan& plan, double iso, int n, const std::string& producer);

/// The budget and what a slab run reports.
struct ScatteredStoreParams {
    std::uint64_t memory_bytes = 1ull << 30;  ///< the budget for the loaded points and their field
    double bytes_per_point = 1200;            ///< what one loaded point costs at first (field and the rest)
    double other_bytes_per_point = 320;       ///< what one loaded point costs beside its field (points, bins,
                                              ///< support test, the slab's output)
    double reg_gap = 4;                       ///< the support test's factor (0: none), as the in-memory path
    /// The stencil layers this run makes, [first, end) along z (a rank's share under mpirun:
    /// stream/scattered_store_ranks.hpp); end -1: to the last layer.
    std::array<std::int64_t, 2> layers{0, -1};
};

struct ScatteredStoreReport {
    int slabs = 0;                 ///< slabs run (a slab widened and run again counts once)
    int retries = 0;               ///< slab runs redone (lacking balls loaded, or a wider halo)
    std::uint64_t most_loaded = 0; ///< the most points loaded for one slab
    std::uint64_t loaded = 0;      ///< points loaded over all slabs (halos counted again)
    double halo_cells = 0;         ///< the widest halo a slab needed, in grid cells along z
    std::uint64_t reused_fits = 0; ///< local fits copied from the slab before (kernels/mpu_fit_cache.hpp)
    double field_seconds = 0, coverage_seconds = 0, read_seconds = 0;
    FieldBuildStats field;         ///< summed over the slabs' fields (locals of their query boxes)
};

/// Runs the isosurface slab by slab into `sink` (finished once at the end): the stencils of
/// sp.layers, in their single-process order. field_params: an mpu
/// field's. np.seed_max_travel must be finite. dedup as run_scattered_isosurface (on the sink
/// side). progress(k): k more stencils done (may be empty). report (optional) gets the figures.
ScatteredIsosurfaceStats run_scattered_store_isosurface(const PointStore& store, const ScatteredStorePlan& plan,
                                                        const FieldParams& field_params, const ScatteredStoreParams& sp,
                                                        double iso, int n, const FieldProjectParams& np, double dedup,
                                                        Sink& sink, const RunOptions& opt,
                                                        const std::function<void(double)>& progress = {},
                                                        ScatteredStoreReport* report = nullptr);

/// How far beyond a slab's stencils its points are loaded at first, world units: Newton's reach
/// (--max-travel) and the first halo (two MPU fit spheres at the mean density, at least two cells).
double store_slab_reach(const ScatteredStorePlan& plan, const FieldParams& field_params, const FieldProjectParams& np);

/// The points a slab of stencil layers [s0, s1) loads at first with that reach (the cell layers its
/// loaded z range meets; lacking balls may add more).
std::uint64_t store_layers_loaded(const ScatteredStorePlan& plan, std::int64_t s0, std::int64_t s1, double reach);

/// The binning line's figures of the plan (what print_scattered_stats writes for points in memory).
BinningSummary binning_summary(const ScatteredStorePlan& plan);

/// The statistics of one slab run to `out`, each line prefixed `cmd: `: binning and stencils, the
/// Newton projection, --dedup (dedup > 0), the slabs (rebuilds, halo, points loaded, the slab
/// fields), the points written and the times (t.graph: the run; threads: its workers).
void print_store_isosurface_stats(std::FILE* out, const char* cmd, const ScatteredStorePlan& plan, const ScatteredStoreReport& rep,
                                  const ScatteredIsosurfaceStats& st, int n, const FieldProjectParams& np, double dedup,
                                  std::size_t points, const IsosurfaceRunTimes& t, int threads);

}  // namespace meshless
