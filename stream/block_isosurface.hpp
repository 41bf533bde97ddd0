// The multiblock/AMR isosurface recipe (dissertation chapter 4, sections 4.3-4.6), the graph
// `meshless isosurface BLOCKS...` and `generate BLOCKS...` run (and any other front end):
//   block cells (stream/block_cell_source.hpp) -> marching-cubes seeds on the barycentric lattice
//   (stream/block_seed_stage.hpp) -> safeguarded Newton onto one continuous meshless field built from
//   every block's valid nodes (stream/field_project_stage.hpp) [-> the splat stage] -> the sink.
// The field is the caller's (kernels/make_field.hpp, or a fitted .mlf): the recipe only runs the
// graph. Memory: the blocks as read + the seed plan (one int64 a block) + the batches in flight.
// The bytes do not depend on the thread count; the --stats lines of a run are written to a FILE*
// here. Throws FormatError for unusable data (named in the message), what the readers and stages
// throw otherwise.
#pragma once
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"
#include "formats/point_stream.hpp"
#include "kernels/block_cell_seeds.hpp"
#include "kernels/field.hpp"
#include "kernels/structured_block.hpp"
#include "stream/block_seed_stage.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/seed_projection.hpp"

namespace meshless {

/// The default lattice parameter n (n(n+1)/2 seeds per triangle), chosen by measurement
/// (combustor combxyz.bin + combq.bin density and multicomb_0..2.vts, iso 0.4, mpu field,
/// one thread; reference = the same surface at n = 8; tolerance = 0.01 x the mean cell diagonal,
/// 0.0058 and 0.0166):
///   n  points (comb / multicomb)  Newton s/core (comb)  splat-plane deviation p99 / tolerance
///   1   10,720 /  1,132           0.085                 3.1 / 4.9
///   2   32,156 /  3,396           0.116                 1.3 / 1.9
///   3   64,313 /  6,792           0.219                 0.93 / 1.1
///   4  107,189 / 11,320           0.349                 0.78 / 0.84
/// Every n covers >= 99.9% of the reference within one splat radius (the radius grows as n
/// shrinks), so coverage does not decide; flatness does: n = 3 is the smallest n whose discs stay
/// within about the Newton tolerance of the surface they stand for (99th percentile), for ~0.1 s
/// more than n = 2 on the combustor (~10% of the whole process, the field build dominating); n = 4
/// costs 67% more points for 15-25% less deviation.
inline constexpr int kDefaultLatticeN = 3;

/// The blocks to contour and their seed plan at one isovalue.
struct BlockIsosurfaceInput {
    Multiblock mb;        ///< as read: the field's data (to_point_set)
    Multiblock padded;    ///< AMR: cell-centred boxes padded to their faces (amr_seed_blocks), else empty
    BlockSeedPlan plan;   ///< of seed_blocks()
    std::string source;   ///< file names joined by ','
    double read_seconds = 0, plan_seconds = 0;
    /// What the seed stage contours.
    const Multiblock& seed_blocks() const { return padded.blocks.empty() ? mb : padded; }
    /// The cells the source hands out (the progress total).
    std::int64_t cells() const { return plan.first_cell.back() - plan.first_cell.front(); }
};

/// Reads `paths` (formats/multiblock_reader.hpp) and plans the seeds at `iso`. `source`: the names
/// the metadata records. FormatError when there are more blocks than block ids can number, or when
/// every node is blanked or non-finite.
BlockIsosurfaceInput read_block_input(const std::vector<std::string>& paths, const PointSetOptions& options,
                                      const std::string& source, double iso);

/// The same over blocks already in memory (`source`: the names the metadata and messages give).
BlockIsosurfaceInput plan_block_isosurface(Multiblock mb, const std::string& source, double iso);

/// What generate writes and isosurface records: the same keys on both paths, so the PLY comments
/// are the same bytes. The frame is the box of the cells the isosurface crosses (the valid nodes'
/// box when none does). n: the lattice parameter; producer: the command line.
StreamMeta block_isosurface_meta(const BlockIsosurfaceInput& in, double iso, int n, const std::string& producer);

/// The field of a job over `in`: build(the blocks' valid nodes) (the caller's: kernels/make_field.hpp,
/// a fitted .mlf), run only when some cell is crossed; and its metadata, block_isosurface_meta(in,
/// iso, n, producer) with the projection's keys (np). kind: the name without a field.
IsosurfaceField fit_block_field(const BlockIsosurfaceInput& in, double iso, int n, const std::string& producer,
                                const FieldProjectParams& np, const std::string& kind,
                                const std::function<BuiltField(const PointSet&)>& build);

/// What one run did.
struct BlockIsosurfaceStats : SeedProjection {  ///< newton, seed/newton busy seconds
    BlockSeedStats seeds;          ///< without a field: only `cells` (planned, not seeded)
    bool projected = false;        ///< a field was given and the graph ran
};

/// Runs cells -> seeds -> Newton onto `field` [-> draw] -> sink with opt.threads workers. A null
/// field (no cell is crossed: an empty output needs none) sends an empty stream (through draw).
/// progress(k): k more cells handed out (may be empty). n: 1..kMaxLatticeN.
BlockIsosurfaceStats run_block_isosurface(const BlockIsosurfaceInput& in, const Field* field, double iso, int n,
                                          const FieldProjectParams& np, const Stage* draw, Sink& sink, const RunOptions& opt,
                                          const std::function<void(double)>& progress = {});

/// The seed stream alone (`meshless generate BLOCKS...`): cells -> seeds -> sink.
BlockSeedStats generate_block_seeds(const BlockIsosurfaceInput& in, double iso, int n, Sink& sink, const RunOptions& opt);

/// The statistics line of the seeds (blocks, cells skipped and why, triangles, seeds of the lattice
/// of parameter n) written to `out`, prefixed `cmd: `.
void print_block_seed_stats(std::FILE* out, const char* cmd, const BlockIsosurfaceInput& in, const BlockSeedStats& s, int n);
/// The statistics of one run to `out`: the seeds, the Newton projection (when one ran, onto
/// `field_name`), the points written and the times (threads: the run's workers).
void print_block_isosurface_stats(std::FILE* out, const char* cmd, const BlockIsosurfaceInput& in, const BlockIsosurfaceStats& st,
                                  int n, const std::string& field_name, const FieldProjectParams& np, std::size_t points,
                                  const IsosurfaceRunTimes& t, int threads);
/// The statistics of the seed stream alone (generate_block_seeds): the seeds and the times
/// (total_seconds: the whole command's).
void print_block_generate_stats(std::FILE* out, const char* cmd, const BlockIsosurfaceInput& in, const BlockSeedStats& seeds, int n,
                                double total_seconds);
}  // namespace meshless
