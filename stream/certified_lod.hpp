// A certified level of detail: the smallest level of detail by count (kernels/cluster_lod.hpp,
// LodMode::count) whose reconstruction by a meshless field is within E of EVERY sample the tree was
// built from, checked at every sample, not estimated. What `meshless lod --max-error E --samples
// INPUT` runs. Dissertation chapter 6 bounds a cluster's own deviation (sigma_c, section 6.3);
// this bounds what a user sees: the field of the LOD's points (section 6.5) at the data.
// Search: the finest LOD is tried first (when it misses E, no LOD of the tree reaches it: the result
// says so and holds the finest); then bisection on the count N in [1, leaves], each trial building
// the field of LOD(N) and evaluating it at every sample (a sample where the field is NaN fails). The
// error need not fall monotonically with N: the result is within E, and LOD(N - 1) was tried and
// missed E (N = 1 excepted), but a smaller N that also reaches E may exist between the trials.
// Units: the samples' world coordinates and data units. Cost: about log2(leaves) + 1 fields built
// and evaluated at every sample. Threads: at most `threads` workers. Throws InvalidArgument when the
// samples are not the tree's (another count or bounds) or E is negative or not finite, and what
// make_field throws.
#pragma once
#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <span>
#include <vector>
#include <string>

#include "kernels/cluster_tree.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_set.hpp"
#include "stream/cluster_hierarchy.hpp"

namespace meshless {

struct CertifiedLod {
    PointSet points;              ///< the LOD, coarse to fine (lod_point_set)
    std::uint64_t count = 0;      ///< its size N
    double max_error = 0;         ///< max over every sample of |field(p_j) - f_j| for this LOD (inf when a field value is NaN or it has fewer than 4 distinct points)
    bool reached = false;         ///< max_error <= E (false: the finest LOD, which misses E)
    int trials = 0;               ///< fields built and evaluated
    std::uint64_t samples = 0;    ///< samples checked per trial
};

/// `trial(count, max_error)` is called after each trial (progress, --stats). `known`: a size already
/// certified within max_error with this `field` (a tree's certificate, certify_lod_sizes): the
/// bisection then runs in [1, known.count] and the finest LOD is not tried.
CertifiedLod certified_lod(const ClusterTree& tree, const PointSet& samples, double max_error, const FieldParams& field, int threads,
                           const std::function<void(std::uint64_t, double)>& trial = {},
                           std::optional<CertifiedError> known = std::nullopt);

/// The LOD counts of `fractions` of the tree's samples (rounded, at least 1, at most the leaves),
/// ascending without repeats. InvalidArgument for a fraction outside (0, 1] or more than
/// kMaxCertifiedErrors sizes.
std::vector<std::uint64_t> certify_counts(const ClusterTree& tree, std::span<const double> fractions);

/// The certified error of LOD(n) for each of `counts` (ascending, within 1..leaves): the largest
/// |field - f_j| over every sample, of the mpu field with Hardy's c relative `hardy_c_rel`, as
/// certified_lod measures it; what `hierarchy --certify` stores in the tree and `info` lists.
/// `trial(count, error)` after each. InvalidArgument for samples that are not the tree's, counts out
/// of order or range, a c outside (0, 100]; what make_field throws.
std::vector<CertifiedError> certify_lod_sizes(const ClusterTree& tree, const PointSet& samples, std::span<const std::uint64_t> counts,
                                              double hardy_c_rel, int threads, const std::function<void(std::uint64_t, double)>& trial = {});

/// `meshless lod TREE --max-error E --samples INPUT -o OUT`: the tree read, its samples read, the
/// certified LOD written to `out` (.ply/.csv/.vtp, formats/point_set_writer.hpp) with a comment saying
/// what was certified and the Hardy c its readers use (formats/field_hint.hpp), which is also the c of
/// the certifying mpu field: `hardy_c_rel`, or a LOD's default for the tree's order. A missed E is a
/// warning line on `warnings`; `stats` (when set) gets the --stats line.
struct CertifiedLodJob {
    std::string tree_path, out;
    TreeSamplesInput samples;
    double max_error = 0;
    std::optional<double> hardy_c_rel;
    int threads = 1;
    std::function<void(double done, double total)> progress;  ///< trials done of an estimated total (log2(splits + 1) + 2)
    std::FILE* warnings = stderr;
    std::FILE* stats = nullptr;
};

/// Throws what certified_lod, the readers and the writer throw; InvalidArgument from certified_lod
/// (samples that are not the tree's) becomes FormatError "SAMPLES: ... (TREE)".
CertifiedLod run_certified_lod_job(const CertifiedLodJob& job);

}  // namespace meshless
