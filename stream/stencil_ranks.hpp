// The scattered-data isosurface (dissertation sections 5.4-5.7: "machines concurrently generate
// isosurface fragments while marching through separate stencils") split across ranks (MPI or any
// RankChannel), streamed to rank 0 in the single-process order (stream/rank_merge.hpp): the stencil
// rows are the units, dealt round-robin (a static deal, not the dissertation's dynamic master/slave:
// rows of a uniform grid interleave dense and sparse regions evenly); each rank runs StencilSource
// (its rows) -> StencilSeedStage -> FieldProjectStage; rank r > 0 sends its points to rank 0, rank 0
// merges into `out`, which receives exactly the points of the single-process graph, in order
// (out.finish() is called). Each rank's statistics cover its own rows only (sum them).
// Throws what the stages, the channel and the sink throw.
#pragma once
#include "stream/field_project_stage.hpp"
#include "stream/rank_merge.hpp"
#include "stream/runner.hpp"
#include "stream/stencil_seed_stage.hpp"

namespace meshless {

struct StencilRankResult {
    StencilSeedStats seeds;
    FieldNewtonStats newton;
};

/// out: rank 0's downstream sink (ignored on other ranks; may be null there).
StencilRankResult run_stencils_rank(const StencilInput& in, double iso, int n, const FieldProjectParams& np, int rank, int ranks,
                                    RankChannel& channel, Sink* out, const RunOptions& opt = {});

}  // namespace meshless
