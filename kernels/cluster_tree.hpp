// The cluster binary tree (CBT) of dissertation chapter 6 as data: one node per cluster, the root
// (node 0) holding every sample, each split adding two children (section 6.3). What the builder
// (kernels/cluster_binary_tree.hpp) makes, the .mlh file (formats/cluster_tree_file.hpp) stores and
// the level-of-detail traversal (kernels/cluster_lod.hpp) reads.
//
// Node numbering: the root is 0; split number s (0-based, in refinement order) gives its two
// children the numbers 2s + 1 (the side behind the splitting plane) and 2s + 2 (on or in front of
// it), so a child's number is always larger than its parent's and the tree holds 2 x splits + 1
// nodes. Units: centres in the input's world units; value and error in its data units.
// Thread-safety: plain data; validate_cluster_tree is reentrant.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

/// Node flags.
inline constexpr std::uint32_t kCbtSkippedSplit = 1;  ///< split attempted, one side was empty: a leaf for good

struct CbtNode {
    Vec3 centre;              ///< p_c, mean of the cluster's sample positions
    double value = 0;         ///< f_c: the local multiquadric over the min(|C|, k) samples nearest p_c, or the mean of the cluster's samples (CbtValueKind)
    double error = 0;         ///< sigma_c = max_j |f_j - f_c| over the cluster, >= 0
    std::uint32_t count = 0;  ///< samples in the cluster, >= 1
    std::uint32_t depth = 0;  ///< root 0
    std::uint32_t child = 0;  ///< first child (the second is child + 1); 0 for a leaf
    std::uint32_t flags = 0;  ///< kCbtSkippedSplit
    bool leaf() const { return child == 0; }
};
static_assert(sizeof(CbtNode) == 56);

/// How the PCA of a cluster's (x, y, z, f) samples weighs position against value (section 6.3).
/// raw: the data's units, as in the dissertation (for 0..255 values over a 100-voxel grid the value
/// dominates); normalised: positions divided by the input's bounding-box diagonal and values by its
/// value range, so both span about 1.
enum class PcaScaling : std::uint32_t { raw = 0, normalised = 1 };
/// "raw" or "normalised" (the --pca-scaling spelling).
inline const char* pca_scaling_name(PcaScaling s) { return s == PcaScaling::raw ? "raw" : "normalised"; }

/// Which cluster the refinement splits next (kernels/cluster_binary_tree.hpp):
/// max_error: the largest sigma_c, as in dissertation section 6.3 (the refinement drives the
/// worst deviation down, and its splits gather at edges and noise);
/// weighted: the largest |C| x (sigma_c^2 + t^2), t = size_term x the value range: a bound on the
/// cluster's squared error summed over its samples, plus a term that splits large quiet clusters
/// too, so the point density of a level of detail does not jump (the fields reconstruct poorly
/// across such jumps). Chosen by measurement (bench/MEASURED.md, "Levels of detail that beat
/// random samples").
enum class CbtSplitOrder : std::uint32_t { max_error = 0, weighted = 1 };
/// "max-error" or "weighted" (the --split-order spelling).
inline const char* split_order_name(CbtSplitOrder o) { return o == CbtSplitOrder::max_error ? "max-error" : "weighted"; }

/// A cluster's value f_c: fit, the local multiquadric at its centre (section 6.3); mean, the mean
/// of its samples (the constant of least squared error over the cluster).
enum class CbtValueKind : std::uint32_t { fit = 0, mean = 1 };
/// "fit" or "mean" (the --cluster-value spelling).
inline const char* cluster_value_name(CbtValueKind v) { return v == CbtValueKind::fit ? "fit" : "mean"; }

struct CbtParams {
    std::uint64_t max_splits = UINT64_MAX;  ///< stop after this many splits
    double max_error = 0;                   ///< stop when the worst queued error is <= this
    std::uint32_t min_cluster = 2;          ///< clusters with fewer samples are never split (>= 2)
    std::uint32_t neighbours = 25;          ///< k: f_c from the min(|C|, k) samples nearest p_c (>= 1)
    double hardy_c_rel = 0.025;             ///< Hardy's c relative to the input's bounding-box diagonal
    double hardy_c_world = 0;               ///< > 0: Hardy's c in world units (overrides hardy_c_rel)
    PcaScaling scaling = PcaScaling::normalised;  ///< default chosen by measurement, see cluster_binary_tree.hpp
    CbtSplitOrder order = CbtSplitOrder::weighted;  ///< default chosen by measurement, see above
    double size_term = 0.2;                 ///< t of the weighted order, relative to the value range, in [0, 100]
    CbtValueKind value = CbtValueKind::mean;  ///< default chosen by measurement, see above
};

struct CbtStats {
    std::uint64_t samples = 0;            ///< samples in the tree (finite ones)
    std::uint64_t dropped_nonfinite = 0;  ///< samples with a NaN/Inf coordinate or value, left out
    std::uint64_t splits = 0;             ///< successful splits (nodes = 2 x splits + 1)
    std::uint64_t skipped = 0;            ///< splits that left one side empty (not re-queued)
    std::uint32_t depth = 0;              ///< deepest node
    double error_reached = 0;             ///< max error over the leaves (the finest LOD's error)
    double hardy_c_world = 0;             ///< c used
    double seconds = 0;                   ///< build time (not stored in files)
    /// splits computed ahead for the threads whose results were never applied because max_splits
    /// ended the refinement first: wasted work (not stored in files)
    std::uint64_t speculative_unused = 0;
    std::uint64_t rounds = 0;             ///< rounds of speculative splitting (not stored in files)
    std::uint64_t memory_bytes = 0;       ///< bytes of the permutation and the nodes (with their ranges) at the end
};

/// The certified error of one level of detail (stream/certified_lod.hpp): the largest |field - f_j|
/// over every sample j the tree was built from, of the mpu field (section 5.5) of LOD(count) with
/// Hardy's c = hardy_c_rel x the LOD's bounding-box diagonal; +inf when that field is NaN somewhere
/// (or the LOD has fewer than 4 distinct points, the least a field is built from). Data units.
struct CertifiedError {
    std::uint64_t count = 0;
    double max_error = 0;
    double hardy_c_rel = 0;
};

/// The most certified errors a tree carries.
inline constexpr std::size_t kMaxCertifiedErrors = 64;

struct ClusterTree {
    std::vector<CbtNode> nodes;
    std::vector<CertifiedError> certified;  ///< by count, ascending (hierarchy --certify); may be empty
    CbtParams params;
    CbtStats stats;
    std::array<Vec3, 2> bounds{};           ///< of the samples
    std::array<double, 2> value_range{0, 0};
    std::string value_name;
    /// sample_set_hash (kernels/sample_set_hash.hpp) of the samples it was built from: what a
    /// certificate checks the given samples against; 0 for trees read from files before version 4.
    std::uint64_t samples_hash = 0;
};

/// Checks the structure: at least one node; children in range, numbered after their parent and
/// referenced once (no cycles, no sharing), child depth = depth + 1, child counts summing to the
/// parent's, counts >= 1, finite centres/values, errors >= 0, flags known (skipped only on
/// leaves), the root's count = `samples`. Returns "" when valid, else what is wrong (node number
/// first: "node 12: ...").
std::string validate_cluster_tree(std::span<const CbtNode> nodes, std::uint64_t samples);

/// splits, skipped, depth and error_reached recomputed from the nodes (a valid tree).
CbtStats cluster_tree_stats(std::span<const CbtNode> nodes);

}  // namespace meshless
