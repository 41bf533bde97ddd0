// Level-of-detail extraction from a cluster binary tree (dissertation section 6.4): a depth-first
// traversal (first child before the second) that, in the level-based mode, takes every node at
// depth L and every leaf above it, and in the error-based mode takes every node whose error is
// <= E, descending otherwise; a leaf met on the way is taken as it is ("we use the cluster at the
// leaf and continue traversal"). The nodes taken, their centres and values, are a scattered data
// set of the field at that resolution (section 6.5).
// A level beyond the depth, an error below the finest LOD's error, or a count above the leaves gives
// the finest LOD (every leaf); the caller warns (LodRequest::clamped tells it).
// The selection is the depth-first one, computed in one sequential pass over the nodes in number
// order (children are numbered after their parents); lod_nodes gives it in node-number order.
// lod_point_set lists it coarse to fine (lod_coarse_to_fine_order): every cluster of the tree is
// represented by one LOD node below it, the one reached through its larger child at every split,
// and the LOD nodes are listed by the depth of the shallowest cluster they represent, so the first
// k nodes hold one node below each cluster of a coarser cut of the tree: any prefix of a LOD is a
// LOD of its size, spread over the whole data (a viewer or a pipe may stop reading early).
// Preconditions: a valid tree (kernels/cluster_tree.hpp validate_cluster_tree).
// Cost: O(nodes) time and 4 bytes per node of scratch, plus the sort of the LOD's nodes.
// Thread-safety: pure functions. Throws only bad_alloc.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/cluster_tree.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

/// level: the clusters at depth L; error: the first clusters of error <= E on every path; count:
/// the leaves after the first N - 1 splits of the refinement (N points, the build's own order:
/// node numbers follow the splits), which for the weighted split order is the level of detail
/// the refinement makes best at that size.
enum class LodMode { level, error, count };

/// The node numbers of the LOD, ascending.
std::vector<std::uint32_t> lod_nodes(std::span<const CbtNode> nodes, LodMode mode, double threshold);

/// `ids` (a LOD, e.g. lod_nodes') reordered coarse to fine (see above): stably by the depth of the
/// shallowest cluster each node represents, node number breaking ties.
std::vector<std::uint32_t> lod_coarse_to_fine_order(std::span<const CbtNode> nodes, std::vector<std::uint32_t> ids);

/// The LOD as a point set (centres, values; one block "lod"), coarse to fine; value_name as given.
PointSet lod_point_set(std::span<const CbtNode> nodes, LodMode mode, double threshold, const std::string& value_name);

/// LOD sizes for every level 0..depth (index = level), in one pass over the nodes.
std::vector<std::uint64_t> lod_sizes_per_level(std::span<const CbtNode> nodes);

/// The size of the error-based LOD at E, without building it.
std::uint64_t lod_size_at_error(std::span<const CbtNode> nodes, double error);

/// True when the request goes beyond the tree (level > depth, or error < the finest LOD's error).
bool lod_request_clamped(std::span<const CbtNode> nodes, LodMode mode, double threshold);

}  // namespace meshless
