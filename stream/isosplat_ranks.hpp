// Paradigm (C) over a brick store split across ranks (MPI or any RankChannel), streamed to rank 0
// in the single-process order (stream/rank_merge.hpp): the active bricks, in Morton order, are the
// units, dealt round-robin; each rank runs BrickSource -> BrickGenerateStage (fused project) over
// its bricks; rank r > 0 sends to rank 0, rank 0 merges into `out` (which then receives exactly
// the batches' points of run_isosplat_bricks over all active bricks, in order; out.finish() is
// called). Each rank's statistics cover its own bricks only (sum them across ranks).
// Throws what the stages, the channel and the sink throw.
#pragma once
#include "stream/isosplat_pipeline.hpp"
#include "stream/rank_merge.hpp"

namespace meshless {

/// out: rank 0's downstream sink (ignored on other ranks; may be null there).
IsoSplatResult run_isosplat_bricks_rank(const BrickStore& store, BrickCache& cache, const std::vector<std::size_t>& active,
                                        int rank, int ranks, double iso, Projection mode, const SamplingParams& sp,
                                        RankChannel& channel, Sink* out, const RunOptions& opt = {});

}  // namespace meshless
