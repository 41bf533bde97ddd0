// Builds the cluster binary tree (CBT) of dissertation sections 6.1 and 6.3 from scattered samples
// (a volume's voxels, a point set, multiblock nodes): one initial cluster of every sample; a
// priority queue ordered by the split priority (kernels/cluster_tree.hpp CbtSplitOrder: the cluster
// error sigma_c as in the dissertation, or |C| x (sigma_c^2 + t^2); largest first, ties by node
// number); the first cluster is split by its PCA plane (kernels/cluster_pca_split.hpp) and its two
// children get their centre, value and error (kernels/cluster_value.hpp) and join the queue; a split
// that leaves one side empty is a skipped split, counted, flagged on the node and not re-queued.
// Clusters of fewer than min_cluster samples, or whose error is <= max_error, are never queued
// (except that the weighted order with a size term and max_error = 0 also splits exact clusters).
// Refinement stops after max_splits splits or when no cluster is left to split (max_error = 0
// refines until every cluster is exact or unsplittable). Node numbers follow the splits, so the
// first s splits' leaves are the s + 1 point level of detail (kernels/cluster_lod.hpp, LodMode::count).
//
// Samples whose position or value is NaN/Inf are left out and counted. InvalidArgument when fewer
// than 2 finite samples remain, when all of them lie at one position, when there are 2^32 or more,
// or for parameters out of range (min_cluster < 2, neighbours < 1, a negative or non-finite max_error
// or Hardy's c). A constant field gives a one-node tree (error 0).
//
// PCA scaling default: normalised. Measured (meshless-bench hierarchy-rmse, bench/MEASURED.md "Hierarchy (issue
// 9)"): RMSE of the mpu field of error-based LODs at 1%, 5% and 15% of the samples against the
// voxels, normalised vs raw: silicium 100.3 vs 104.7, 118.1 vs 113.2, 38.7 vs 50.1; head (64x64x93)
// 409 vs 443, 418 vs 496, 256 vs 316; LIDC2 1347 vs 1414, 638 vs 576, 457 vs 383: normalised lower
// in 6 of 9. raw stays available.
//
// Threads: the per-cluster work runs on oneTBB. Splits are computed ahead in rounds and applied
// in exactly the serial order, numbering the nodes as a serial run would; each split is a pure
// function of its cluster's samples, and clusters occupy disjoint ranges of the index permutation.
// The serial order splits clusters in falling priority p = the smallest split priority on the path from the
// root (a best-first search pops its nodes in falling path minimum), so a round picks a threshold
// tau and computes, on parallel tasks, every queued cluster with p >= tau and every descendant with
// p >= tau (subtrees are independent); the serial loop then applies results until it reaches a
// cluster not computed, and the next round starts. tau is the p of the m-th worst queued cluster,
// m sized from the last round's growth (splits made per queued cluster started from) so that a
// round makes about half the splits left (at most max(4096, splits / 16) / 2), never more than
// twice the last m; a round computes at most the splits left + 64. The rounds depend only on the
// data, not on the thread count (the budget aside), so every thread count does the same work.
// Measured on the x2 head (2,983,865 samples, 300,000 splits): 56 rounds, 1 split computed and
// never applied (CbtStats::speculative_unused, rounds; in hierarchy --stats); the batches of 16
// clusters per core this replaced made ~40,000 barriers and 1.44x on 2 threads, rounds 1.84x.
// When max_splits allows every split, one round computes the whole tree. Clusters of
// chunks::kParallelItems samples or more are themselves processed in fixed chunks in parallel. The
// tree is identical, bit for bit, for any thread count. Limit threads with tbb::global_control.
// Memory: the samples are not copied: one u32 permutation of the sample numbers (4 bytes/sample),
// the nodes (56 bytes each, 2 x splits + 1), their index range starts, value means and computed
// split (16 bytes/node), the queue (24 bytes per entry) and the splits computed and not yet applied
// (112 bytes each, at most a round's); partitions are in place.
// Thread-safety: reentrant. Throws InvalidArgument (above) or std::bad_alloc.
#pragma once
#include <span>

#include "kernels/cluster_tree.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

/// Optional progress callback: called with the splits computed so far (rising; at the end the
/// splits made plus the few computed in vain), the samples settled (in computed clusters that will
/// not be split: error <= max_error, fewer than min_cluster samples, or a skipped split; all of them
/// when a build without max_splits ends) and the splits applied to the tree (the serial order's
/// pops, after the rounds that computed them), every 1,024 splits computed or applied and after each
/// round, by one thread at a time but not always the caller's. Settled samples measure a --max-error
/// build, whose split count is not known in advance; computing and applying take about equal time
/// (24 s of a 69 M-sample build: 13 s and 11 s); a split costs about its cluster's samples, so the
/// first splits of a --max-splits build are the dear ones (work).
struct CbtProgressReport {
    std::uint64_t computed = 0;  ///< splits computed
    std::uint64_t settled = 0;   ///< samples in clusters that will not be split
    std::uint64_t applied = 0;   ///< splits applied to the tree
    std::uint64_t work = 0;      ///< samples the computed splits took (a split of c samples costs about c)
};
struct CbtProgress {
    virtual ~CbtProgress() = default;
    virtual void splits_done(const CbtProgressReport& r) = 0;
};

ClusterTree build_cluster_tree(std::span<const Vec3> pos, std::span<const double> value, const CbtParams& params,
                               CbtProgress* progress = nullptr);

}  // namespace meshless
