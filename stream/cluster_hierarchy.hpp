// The cluster-hierarchy recipes (dissertation chapter 6, sections 6.3-6.5), what `meshless
// hierarchy` and `meshless lod` run, and any other front end: the cluster binary tree of a point set
// built under a thread count, its data errors naming the input, with the notes and the --stats line
// of a build; and a level of detail extracted from a tree with the warning about cluster values
// beyond the samples' range and its --stats line. docs/architecture.md "Costly builds are files"
// says why the tree is saved (.mlh, formats/cluster_tree_file.hpp).
// Units: world coordinates and the data's values; seconds; MiB in the report.
// Throws FormatError ("INPUT: ...") when the data cannot make a tree; InvalidArgument from
// build_cluster_tree for parameters out of their domain.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "formats/point_set_reader.hpp"
#include "kernels/cluster_binary_tree.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

/// The most splits a build of `samples` samples with `p` makes (a leaf per sample, or
/// p.max_splits; --max-error may stop sooner): the total of a progress line.
double cluster_hierarchy_split_bound(const CbtParams& p, std::size_t samples);

/// build_cluster_tree of `points` with at most `threads` workers, progress(splits done) after each
/// round when given; the tree counts the points' dropped NaN/Inf samples and takes their value name.
/// A data error (InvalidArgument "cluster tree: ...") becomes FormatError "INPUT: ...".
ClusterTree build_cluster_hierarchy(const PointSet& points, const CbtParams& p, int threads, const std::string& input,
                                    const std::function<void(std::uint64_t)>& progress = {});

/// The warnings and notes of a build, one line each without the command's name ("warning: N
/// samples with NaN/Inf ... dropped", "note: ... a one-node tree").
std::vector<std::string> cluster_hierarchy_notes(const ClusterTree& tree, const CbtParams& p);

/// The --stats line of a build (no newline): "hierarchy: N samples, ... rounds".
std::string cluster_hierarchy_report(const ClusterTree& tree, const CbtParams& p, int threads, double read_seconds,
                                     double write_seconds);

/// A level of detail of a tree (section 6.4) as a scattered point set (section 6.5).
struct LodExtraction {
    PointSet points;
    double seconds = 0;        ///< the extraction's time
    std::size_t outside = 0;   ///< cluster values outside the tree's value range
    double lo = 0, hi = 0;     ///< the range of the values, the tree's widened by those outside
};

/// The LOD of `t` that `r` asks (cluster_tree_lod_request).
LodExtraction extract_lod(const ClusterTree& t, const ClusterTreeLodRequest& r);

/// The warning (without the command's name; empty when none) about cluster values outside the
/// samples' range: a cluster's value is its fit's at its centre (section 6.3), which with rough data
/// can overshoot.
std::string lod_overshoot_warning(const ClusterTree& t, const LodExtraction& e);

/// The --stats line of an extraction from the tree at `path` (no newline): "lod: DESC of PATH: ...".
std::string lod_report(const ClusterTree& t, const ClusterTreeLodRequest& r, const std::string& path, const LodExtraction& e);

}  // namespace meshless
