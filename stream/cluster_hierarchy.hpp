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
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "formats/point_set_reader.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/cluster_binary_tree.hpp"
#include "kernels/point_set.hpp"
#include "stream/field_data.hpp"

namespace meshless {

/// What a tree is built from: `hierarchy INPUT...` and `lod --max-error E --samples INPUT`.
struct TreeSamplesInput {
    std::vector<std::string> paths;
    PointSetOptions points;          ///< the point readers' options (--strict, --value, ...)
    RawOptions raw;                  ///< a raw volume's description and the array to read
    bool raw_given = false;          ///< the caller described a raw volume (--dims/--type/--spacing/--series/--array)
    bool array_given = false;        ///< the caller named an array (refused for a brick store: it holds one)
    std::string command = "hierarchy";  ///< for the messages
    InputWarning warn;               ///< hears of readers' warnings (a level of detail beyond a tree)
};

/// The samples of a tree: a brick store brick by brick, a raw volume as `raw` describes it, or
/// volumes, point sets and multiblock grids as every point command reads them (stream/field_data.hpp;
/// NaN/Inf samples counted, not warned: the tree's notes count them). InvalidArgument for a raw
/// description with several inputs or an array of a brick store; the readers' errors.
PointSet read_tree_samples(const TreeSamplesInput& in);

/// The most splits a build of `samples` samples with `p` makes (a leaf per sample, or
/// p.max_splits; --max-error may stop sooner): the total of a progress line.
double cluster_hierarchy_split_bound(const CbtParams& p, std::size_t samples);

/// Whether a build's progress is better measured in samples settled than in splits: a --max-error
/// build that no max_splits stops, whose split count is not known in advance (the bound of
/// cluster_hierarchy_split_bound is a leaf per sample, far above what it makes).
bool cluster_hierarchy_counts_settled(const CbtParams& p, std::size_t samples);

/// The fraction of a build done, 0..1, for a progress line: computing the splits and applying them
/// weighed equally (they take about equal time); computing measured in samples settled when
/// cluster_hierarchy_counts_settled, else in the samples the splits took of about samples x
/// log2(bound + 1) (a balanced tree's), applying in splits of those computed (of the bound).
double cluster_hierarchy_progress(const CbtParams& p, std::size_t samples, const CbtProgressReport& b);

/// build_cluster_tree of `points` with at most `threads` workers, progress(report) after each round
/// and every 1,024 splits computed or applied when given (kernels/cluster_binary_tree.hpp); the tree counts the points' dropped NaN/Inf samples and takes their value name.
/// A data error (InvalidArgument "cluster tree: ...") becomes FormatError "INPUT: ...".
ClusterTree build_cluster_hierarchy(const PointSet& points, const CbtParams& p, int threads, const std::string& input,
                                    const std::function<void(const CbtProgressReport&)>& progress = {});

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

/// `meshless lod TREE (--count | --fraction | --level | --error) -o OUT`: the LOD that `request`'s
/// lod_* asks of the tree at `tree_path`, written to `out` (.ply/.csv/.vtp) with its description and
/// the Hardy c its points reconstruct best with (formats/field_hint.hpp); a clamped request and
/// overshooting cluster values are warning lines on `warnings`, `stats` (when set) gets the --stats line.
LodExtraction run_lod_job(const std::string& tree_path, const PointSetOptions& request, const std::string& out, std::FILE* warnings,
                          std::FILE* stats);

}  // namespace meshless
