// Paradigm (C) iso-splatting in one process (dissertation sections 3.3-3.6): CellRowSource,
// SlabSource or BrickSource -> [first] -> GenerateStage -> ProjectStage -> [last] -> sink, through
// the runner: the one chapter-3 graph (`meshless isosurface`, `demo`, `generate`, `batch` and the
// library all build it here). The same stages, joined by pipes
// (meshless generate | meshless project | ...), give the same batches in the same order, hence the
// same output bytes. Throws what the sink throws (IoError, BrokenPipe).
#pragma once
#include <cstdio>
#include <string>

#include "kernels/cell_sampling.hpp"
#include "kernels/project_sample.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/slice_source.hpp"
#include "stream/runner.hpp"
#include "stream/sample_store_source.hpp"
#include "stream/stage.hpp"

namespace meshless {

struct IsoSplatResult {
    SamplingStats sampling;
    ProjectionStats projection;
    double seconds = 0;  ///< wall time of generate + project + sink
};

/// The statistics line of one isosurface run (`path` at `iso`: active cells, points, the
/// projection's discards, the NaN/Inf cells skipped, wall time on nthreads x ranks) written to `out`.
void print_isosplat_stats(std::FILE* out, const std::string& path, double iso, Projection mode, const IsoSplatResult& r,
                          std::size_t points, int nthreads, int ranks);

/// How the stages are arranged: `fused` generates and projects in one stage (no SampleRecords are
/// stored); `two_stage` runs the generate and project stages one after the other, exactly as the
/// piped commands do (same bytes as fused); `samples_only` stops after generation (the sink gets
/// sample batches: what `meshless generate` writes; `mode` is unused).
enum class PipelineShape { fused, two_stage, samples_only };

/// Stages a caller adds around generate + project: `first` sees the source's batches (a
/// ProgressStage counting cell rows, stream/progress_stage.hpp), `last` the projected points (the
/// splat sink's draw stage, run in the runner's parallel section). Either may be null. Neither
/// changes the batches, so the sink gets the same bytes with or without them. `before_last` (may be
/// null) does: it sees the projected points before `last` (--color-by's values, ColorByStage).
struct IsoSplatStages {
    const Stage* first = nullptr;
    const Stage* last = nullptr;
    const Stage* before_last = nullptr;  ///< on the projected points, before `last` (ColorByStage)
};
IsoSplatResult run_isosplat(const VolumeView& v, double iso, Projection mode, const SamplingParams& sp,
                            Sink& sink, const RunOptions& opt = {}, PipelineShape shape = PipelineShape::fused,
                            const IsoSplatStages& extra = {});

/// The same over a brick store: the given bricks (normally BrickIndex::active(iso), Morton order)
/// through the byte-budgeted cache.
IsoSplatResult run_isosplat_bricks(const BrickStore& store, BrickCache& cache, std::vector<std::size_t> bricks,
                                   double iso, Projection mode, const SamplingParams& sp, Sink& sink,
                                   const RunOptions& opt = {}, PipelineShape shape = PipelineShape::fused,
                                   const IsoSplatStages& extra = {});

/// The same over a volume streamed slab by slab (stream/slab_source.hpp): memory is a few chunks
/// of slices, never the volume; same bytes as run_isosplat on the whole volume.
IsoSplatResult run_isosplat_slabs(SliceSource& slices, double iso, Projection mode, const SamplingParams& sp,
                                  Sink& sink, const RunOptions& opt = {}, PipelineShape shape = PipelineShape::fused,
                                  const IsoSplatStages& extra = {});

/// Paradigm (A) (section 3.5, Table 3.1): the candidate cell rows of a sample store's span-space
/// index for iso, recomputed from its brick store by `source` (stream/sample_store_source.hpp; made
/// by the caller before its outputs, so that a damaged index fails before any output exists),
/// projected onto `iso` (any shape but samples_only) or not (samples_only: what `meshless extract`
/// writes); the same records as run_isosplat_bricks over the store's .mlb. The result's
/// sampling.active_cells counts the samples the store gave.
IsoSplatResult run_isosplat_sample_store(SampleStoreSource& source, double iso, Projection mode, Sink& sink,
                                         const RunOptions& opt = {},
                                         PipelineShape shape = PipelineShape::two_stage, const IsoSplatStages& extra = {});

}  // namespace meshless
