// The scattered-data isosurface (dissertation sections 5.4-5.7: "machines concurrently generate
// isosurface fragments while marching through separate stencils") split across ranks (MPI or any
// RankChannel), streamed to rank 0 in the single-process order (stream/rank_merge.hpp). The units
// are the stencil rows, dealt dynamically (stream/unit_deal.hpp, the dissertation's master/slave):
// every rank, rank 0 included, asks for its next row when its graph is ready for more, so ranks on
// slower machines, or with the dense rows, simply take fewer. Each rank runs StencilSource (its
// rows) -> StencilSeedStage -> FieldProjectStage; rank r > 0 sends its points to rank 0, rank 0
// merges into `out`, which receives exactly the points of the single-process graph, in order
// (out.finish() is called), whatever the deal was. Each rank's statistics cover its own rows only
// (sum them).
// Throws what the stages, the channel and the sink throw; rank 0 rethrows the deal service's error
// unless on_deal_error takes it (MPI: end the job).
#pragma once
#include <exception>
#include <functional>
#include <vector>

#include "stream/field_project_stage.hpp"
#include "stream/rank_merge.hpp"
#include "stream/runner.hpp"
#include "stream/stencil_seed_stage.hpp"

namespace meshless {

struct StencilRankResult {
    StencilSeedStats seeds;
    FieldNewtonStats newton;
    std::vector<std::size_t> rows_per_rank;  ///< rank 0 only: the rows each rank was dealt
};

/// out: rank 0's downstream sink (ignored on other ranks; may be null there).
StencilRankResult run_stencils_rank(const StencilInput& in, double iso, int n, const FieldProjectParams& np, int rank, int ranks,
                                    RankChannel& channel, Sink* out, const RunOptions& opt = {},
                                    std::function<void(std::exception_ptr)> on_deal_error = {});

}  // namespace meshless
