// The scattered-data isosurface recipe (dissertation chapter 5, sections 5.3-5.6), the graph
// `meshless isosurface POINTS` and `generate POINTS` run (and any other front end):
//   the binning grid (kernels/scattered_binning_grid.hpp) -> marching 3x3x3 stencils
//   (stream/stencil_source.hpp), each regularised on the fly, tetrahedralised by CGAL and contoured
//   by marching tetrahedra, seeded on the barycentric lattice (stream/stencil_seed_stage.hpp) ->
//   safeguarded Newton onto the meshless field (stream/field_project_stage.hpp) [-> the splat
//   stage] -> the sink (optionally through stream/dedup_sink.hpp).
// The field is the caller's (kernels/make_field.hpp or a fitted .mlf); build_alongside_coverage
// overlaps its build with the regularisation's support test. Memory: the points + their bins (4
// bytes a binning cell) + the support test's kd-tree + the batches in flight. The bytes do not
// depend on the thread count. Under MPI (or any RankChannel) run_scattered_isosurface_rank splits the
// stencil rows over the ranks (stream/stencil_ranks.hpp) and sum_stencil_rank_stats sums their
// statistics. The --stats lines of each run are written to a FILE* here. Throws FormatError for
// unusable data (fewer than 4 distinct points), what the kernels and stages throw otherwise.
#pragma once
#include <array>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <functional>
#include <memory>
#include <string>

#include "formats/point_stream.hpp"
#include "kernels/field.hpp"
#include "kernels/point_coverage.hpp"
#include "kernels/point_set.hpp"
#include "kernels/scattered_binning_grid.hpp"
#include "stream/field_data.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/seed_projection.hpp"
#include "stream/stencil_ranks.hpp"
#include "stream/stencil_seed_stage.hpp"

namespace meshless {

/// The default lattice parameter of the scattered path, by measurement (20,000 samples of the
/// bucky volume, iso 100, rbf-grid field, 800 x 800 picture): the marching-tetrahedra triangles are
/// about the data's spacing, smaller than the multiblock cells of kDefaultLatticeN's measurement;
/// n = 1 (56 K points) leaves visible blotches at silhouettes where one disc stands for a whole
/// triangle, n = 2 (169 K points) gives a picture indistinguishable from n = 3 (339 K points) for
/// half the Newton work.
inline constexpr int kScatteredLatticeN = 2;

/// The points, binned (section 5.3), and the regularisation's support test.
struct ScatteredIsosurfaceInput {
    PointSet points;
    BinningGrid grid;
    BinnedPoints bins;
    std::unique_ptr<PointCoverage> coverage;  ///< reg_gap > 0, built by build_alongside_coverage
    double reg_gap = 0;  ///< a regularisation point farther than this x the local spacing gets no value (0: all get one)
    std::string source;  ///< the names the metadata records
    double read_seconds = 0, octree_seconds = 0, coverage_seconds = 0;
    /// Whether iso lies within the data's values (else there is no surface and no field is needed).
    bool crosses(double iso) const;
    /// StencilInput over `field` (alive as long as this input and the field).
    StencilInput stencils(const Field& field) const;
};

/// Bins `points` (section 5.3). `name`: the file the messages name. warn (may be empty: no
/// warnings, and the largest stencil is not counted): a plane or line of points, a coarsened grid,
/// one stencil with most of the points (section 5.8; points the reader dropped as NaN/Inf are
/// read_field_points' warning). Throws
/// FormatError when fewer than 4 positions are distinct.
ScatteredIsosurfaceInput bin_scattered_points(PointSet points, const std::string& source, const std::string& name,
                                              const BinningGridParams& bp, double reg_gap, const InputWarning& warn);

/// Runs build() (the field's build) and the support test's (when in.reg_gap > 0) side by side
/// under `threads` workers: each has serial parts (the support test's kd-tree; the field's merge
/// of near-duplicates and octree root) that the other's parallel parts overlap (10^6 points, 2
/// threads: 17.0 -> 15.4 s whole process). Returns build()'s own seconds; the bits do not depend on
/// the thread count.
double build_alongside_coverage(ScatteredIsosurfaceInput& in, int threads, const std::function<void()>& build);

/// The field of a job over `in`: build() (the caller's: kernels/make_field.hpp, a fitted .mlf, the
/// ranks' shared fits), run only when iso crosses the data, side by side with the support test
/// (build_alongside_coverage, `threads` workers); and its metadata, scattered_isosurface_meta(in,
/// iso, n, producer), with np (an isosurface, not the seeds alone) widened for np's travel
/// (widen_frame_for_travel) and with the projection's keys (add_projection_meta). kind: the name
/// without a field.
IsosurfaceField fit_scattered_field(ScatteredIsosurfaceInput& in, double iso, int n, const std::string& producer,
                                   const FieldProjectParams* np, int threads, const std::string& kind,
                                   const std::function<BuiltField()>& build);

/// What generate writes and isosurface records (the same keys on both paths). The camera's frame:
/// the binning grid with its border layer, where the regularisation points lie and so the
/// stencils' tetrahedra and the seeds, widened by how far Newton may move a seed
/// (kDefaultMaxTravel cell diagonals; a longer travel widens it further, widen_frame_for_travel),
/// so that every point lies inside the recorded bounds. Degenerate axes keep the points' extent.
StreamMeta scattered_isosurface_meta(const ScatteredIsosurfaceInput& in, double iso, int n, const std::string& producer);
/// The same from the grid, the point count and value range, and the source's name (a point store
/// read slab by slab: stream/scattered_store_isosurface.hpp).
StreamMeta scattered_isosurface_meta(const BinningGrid& grid, std::uint64_t points, const std::array<double, 2>& range,
                                     const std::string& source, double iso, int n, const std::string& producer);

/// The most data points one 3x3x3 stencil holds (before regularisation), from the bins' start
/// offsets (order may be empty).
std::int64_t largest_stencil_points(const BinningGrid& g, const BinnedPoints& b);

/// bin_scattered_points' warnings about the grid of `points` points: a plane or line of points, a
/// coarsened grid, one stencil (holding `largest` points) with most of the points (section 5.8).
void warn_about_binning(const BinningGrid& grid, std::int64_t largest, std::uint64_t points, const std::string& name,
                        const BinningGridParams& bp, const InputWarning& warn);

/// What one run did.
struct ScatteredIsosurfaceStats : SeedProjection {  ///< newton, seed/newton busy seconds
    StencilSeedStats seeds;
    std::int64_t dedup_removed = 0;
    bool projected = false;  ///< a field was given and the graph ran
};

/// Runs stencils -> seeds -> Newton onto `field` [-> draw] -> sink with opt.threads workers. A null
/// field (iso outside the data) sends an empty stream (through draw). dedup > 0: points closer than
/// dedup x their radius to an earlier one are removed on the sink side, in sequence order (draw
/// must then be null and the sink draw). progress(k): k more stencils handed out (may be empty).
ScatteredIsosurfaceStats run_scattered_isosurface(const ScatteredIsosurfaceInput& in, const Field* field, double iso, int n,
                                                  const FieldProjectParams& np, double dedup, const Stage* draw, Sink& sink,
                                                  const RunOptions& opt, const std::function<void(double)>& progress = {});

/// The seed stream alone (`meshless generate POINTS`): stencils -> seeds -> sink (an empty stream
/// without a field).
StencilSeedStats generate_scattered_seeds(const ScatteredIsosurfaceInput& in, const Field* field, double iso, int n, Sink& sink,
                                          const RunOptions& opt);

/// One rank's part of run_scattered_isosurface under a RankChannel (stream/stencil_ranks.hpp): the
/// stencil rows dealt on request, rank 0 merging every rank's points into `out` in the
/// single-process order (out is ignored on other ranks). dedup as run_scattered_isosurface (rank 0's
/// side). A null field (iso outside the data) sends an empty stream and needs no channel (channel
/// may then be null); otherwise every rank runs with one. Each rank's statistics cover its own rows
/// (sum_stencil_rank_stats).
StencilRankResult run_scattered_isosurface_rank(const ScatteredIsosurfaceInput& in, const Field* field, double iso, int n,
                                                const FieldProjectParams& np, double dedup, int rank, int ranks,
                                                RankChannel* channel, Sink* out, const RunOptions& opt,
                                                std::function<void(std::exception_ptr)> on_deal_error = {});

/// Every rank's statistics summed by sum_to_root (element-wise over the ranks, the result on rank 0;
/// collective): rank 0 gets the totals (the largest stencil and rows_per_rank: its own figures);
/// other ranks' results are meaningless.
StencilRankResult sum_stencil_rank_stats(const StencilRankResult& mine,
                                         const std::function<std::vector<std::int64_t>(const std::vector<std::int64_t>&)>& sum_to_root);

/// The binning line of the statistics: the grid, the points, the empty cells.
struct BinningSummary {
    const BinningGrid& grid;
    std::uint64_t points, dropped;
    std::int64_t empty, empty_interior;
    std::uint32_t max_per_cell;
};
/// Of points binned in memory (a point store's plan: stream/scattered_store_isosurface.hpp).
BinningSummary binning_summary(const ScatteredIsosurfaceInput& in);

/// The statistics lines of the binning (section 5.3) and the stencils (regularisation, Delaunay,
/// marching tetrahedra, seeds on the lattice of parameter n) written to `out`, each prefixed `cmd: `.
void print_scattered_stats(std::FILE* out, const char* cmd, const BinningSummary& b, const StencilSeedStats& s, int n);
/// The statistics line of --dedup (the fraction and the points it removed).
void print_dedup_stats(std::FILE* out, const char* cmd, double dedup, std::int64_t removed);
/// The statistics of one in-memory run to `out`: binning and stencils, the Newton projection (when
/// one ran, onto `field_name`), --dedup (dedup > 0), the points written and the times (threads: the
/// run's workers).
void print_scattered_isosurface_stats(std::FILE* out, const char* cmd, const ScatteredIsosurfaceInput& in,
                                      const ScatteredIsosurfaceStats& st, int n, const std::string& field_name,
                                      const FieldProjectParams& np, double dedup, std::size_t points,
                                      const IsosurfaceRunTimes& t, int threads);
/// The same of a run split over `ranks` ranks (sum_stencil_rank_stats' totals, on rank 0; the
/// Newton busy time unknown; t.graph unused).
void print_scattered_ranks_stats(std::FILE* out, const char* cmd, const ScatteredIsosurfaceInput& in, const StencilRankResult& tot,
                                 int n, const std::string& field_name, const FieldProjectParams& np, std::size_t points, int ranks,
                                 const IsosurfaceRunTimes& t, int threads);
/// The statistics of the seed stream alone (generate_scattered_seeds): binning and stencils, the
/// times (t.field: the field's build, t.total; t.graph unused).
void print_scattered_generate_stats(std::FILE* out, const char* cmd, const ScatteredIsosurfaceInput& in, const StencilSeedStats& seeds,
                                    int n, const IsosurfaceRunTimes& t);
/// The warning (to `out`) when fewer than half of the projected seeds converged onto the field's
/// isosurface (the field does not resolve the points there); nothing otherwise.
void warn_if_unconverged(std::FILE* out, const std::string& source, const ScatteredIsosurfaceStats& st,
                         const std::string& field_name);

}  // namespace meshless
