// The PCA split of a cluster (dissertation section 6.3, Figures 6.2-6.4): the plane through the
// cluster centre p_c whose normal is the xyz part of the dominant eigenvector e1 of the 4x4
// covariance of the cluster's (x, y, z, f) samples, or of e2 when that projection vanishes
// (|xyz(e1)| <= 1e-9, e1 along the value axis); the samples behind the plane (dot(p - p_c, n) < 0)
// go to the first sub-cluster, the others (on or in front of it) to the second.
//
// Scaling: positions are multiplied by `pos_scale` and values by `value_scale` before the
// covariance (kernels/cluster_tree.hpp, PcaScaling). The position scale is isotropic, so the
// plane normal in world space is the xyz part of the eigenvector as it is.
// Determinism: sums run in fixed chunks (kernels/fixed_chunks.hpp); the partition of a cluster of
// fewer than chunks::kParallelItems samples is std::partition in place; a larger one is partitioned
// chunk by chunk (std::partition, in parallel) and the runs are merged pairwise by rotations in a
// fixed tree order, in place too (no buffer). Chunks, merge order and hence the permutation depend
// only on the cluster size, so the result is the same for any thread count.
// Units: world for positions, data units for values. Throws only std::bad_alloc.
// Thread-safety: reentrant; concurrent calls on disjoint index ranges are safe.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "kernels/vec3.hpp"

namespace meshless {

struct ClusterSplitPlane {
    Vec3 normal;            ///< unit normal (world); {0,0,0} when the cluster has no spatial extent
    bool second = false;    ///< e2 was used (e1 had no xyz part)
};

/// The splitting plane's normal of the samples idx[*] (>= 1), given their mean position `centre`
/// and mean value `mean_value`.
ClusterSplitPlane pca_split_plane(std::span<const Vec3> pos, std::span<const double> value,
                                  std::span<const std::uint32_t> idx, const Vec3& centre, double mean_value,
                                  double pos_scale, double value_scale);

/// Reorders idx so the samples behind the plane through `centre` with `normal` come first; returns
/// how many there are (0 or idx.size() when one side is empty: a skipped split).
std::size_t partition_by_plane(std::span<const Vec3> pos, std::span<std::uint32_t> idx, const Vec3& centre,
                               const Vec3& normal);

}  // namespace meshless
