// The scattered-data isosurface of a point store (.mlc) shared out across ranks by its data, not
// only its work (dissertation sections 5.4-5.7, "machines concurrently generate isosurface fragments
// while marching through separate stencils"; docs/architecture.md "Fields out of core" and
// "Distribution"): rank r takes a contiguous range of stencil layers along z (store_layers_of_rank:
// cut so that the largest number of points a rank loads, its halos counted, is least) and runs it slab by slab within its own --memory
// (stream/scattered_store_isosurface.hpp), loading only the bricks its slabs and their halos meet and
// building only their field. So each rank holds about 1/N of the points and of the field (plus the
// halos of its two ends), where the in-memory MPI path (stream/scattered_isosurface_mpi.hpp) gives
// every rank every point and the whole field. Rank r > 0 sends its points to rank 0 as unit r
// (stream/rank_merge.hpp), rank 0 writes its own then every other rank's in rank order, which is the
// single-process order: the bytes equal the one-process run's for any number of ranks, budget and
// thread count. --dedup runs on rank 0's side over the merged stream.
// Units: isovalue in the points' value units; memory in bytes, each rank's own; dedup a fraction of
// the point radius. Throws what run_scattered_store_isosurface throws (on the rank that fails: a
// front end ends the job with MpiSession::abort), and FormatError from the channel.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "stream/rank_merge.hpp"
#include "stream/scattered_store_isosurface.hpp"

namespace meshless {

/// The first stencil layer of each of `ranks` ranges (ranks >= 1): contiguous, in rank order, covering
/// every layer once, cut so that the most points any range loads with its halos (store_layers_loaded
/// with `reach`, store_slab_reach) is the least it can be; ranks beyond what lowers it take the widest
/// ranges' halves, and ranks beyond the layers get empty ranges at the end.
std::vector<std::int64_t> store_rank_starts(const ScatteredStorePlan& plan, int ranks, double reach);
/// Stencil layers [first, end) of rank `rank` of `ranks` (store_rank_starts).
std::array<std::int64_t, 2> store_layers_of_rank(const ScatteredStorePlan& plan, int rank, int ranks, double reach);

struct StoreRankResult {
    ScatteredIsosurfaceStats stats;    ///< this rank's stencils (summed over ranks by sum_store_rank_stats)
    ScatteredStoreReport report;       ///< this rank's slabs
    std::array<std::int64_t, 2> layers{0, 0};
    std::uint64_t peak_rss = 0;        ///< bytes, this process's high-water mark (set by the caller before summing)
};

/// One rank's own figures, as rank 0 gathers them.
struct StoreRankShare {
    std::uint64_t most_loaded = 0;     ///< the most points one of its slabs loaded
    std::uint64_t peak_rss = 0;        ///< bytes
};

/// One rank's share (collective over `channel`'s ranks): sp.layers is replaced by the rank's range.
/// out: rank 0's downstream sink (finished there; ignored on other ranks, may be null). progress:
/// this rank's stencils as they are done.
StoreRankResult run_scattered_store_rank(const PointStore& store, const ScatteredStorePlan& plan, const FieldParams& field_params,
                                         ScatteredStoreParams sp, double iso, int n, const FieldProjectParams& np, double dedup,
                                         int rank, int ranks, RankChannel& channel, Sink* out, const RunOptions& opt,
                                         const std::function<void(double)>& progress = {});

/// Every rank's figures on rank 0 (collective; sum_to_root: an element-wise sum of int64 vectors over
/// the ranks, to rank 0): counts summed, the most points a slab loaded and the largest slab field the
/// largest of any rank, seconds summed (busy seconds). shares (rank 0, optional): each rank's own figures.
StoreRankResult sum_store_rank_stats(const StoreRankResult& mine, int rank, int ranks,
                                     const std::function<std::vector<std::int64_t>(const std::vector<std::int64_t>&)>& sum_to_root,
                                     std::vector<StoreRankShare>* shares = nullptr);

}  // namespace meshless
