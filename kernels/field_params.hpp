// Parameters and build statistics of the meshless fields (dissertation sections 2.1.1, 4.3, 5.5):
// which field, the RBF-grid binning constant m, the MPU threshold N and sphere factor alpha, and
// Hardy's multiquadric constant c.
//
// Hardy's c (section 2.1.1): the paper fixes c = 0.025 for data normalised to its experiments. Here
// c is given relative to a documented length scale so that one default works for data in metres or
// in voxels:  c_world = hardy_c_rel x (diagonal of the bounding box of the data points), unless
// hardy_c_world > 0, which is used as is (world units). hardy_c_world_for() computes it.
//
// Near-duplicate points: two points closer than merge_rel x h are merged (first position kept,
// values averaged), where h = (prod of the non-degenerate bounding-box extents / n)^(1/k) is the
// mean point spacing (k = number of non-degenerate axes). See kernels/merge_near_duplicates.hpp.
//
// Plain data, no invariants beyond the documented ranges (make_field() checks them and throws
// InvalidArgument). Thread-safe as a value.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <functional>
#include <vector>
#include <span>
#include <string>
#include <string_view>

#include "kernels/vec3.hpp"

namespace meshless {

enum class FieldKind : std::uint8_t {
    rbf_grid,    ///< section 4.3: local multiquadrics at RBF-grid cell centres, PU blended
    mpu,         ///< section 5.5: local multiquadrics at octree leaves (sphere alpha*d, <= N points)
    global_rbf,  ///< section 2.1.1: Hardy's global interpolant over all points (small sets only)
};

/// How far the partition-of-unity weights of the RBF grid reach (see kernels/rbf_grid_field.hpp).
enum class RbfGridSupport : std::uint8_t {
    /// Default. Blend the 27 neighbouring cells as section 4.3 evaluates, with the weight radius
    /// shrunk to 1.5 x (smallest cell edge) so that no centre outside those 27 cells has a non-zero
    /// weight: the field is continuous. (The paper's weight radius 2*|s| with only 27 neighbours is
    /// not: centres two cells away still weigh at x, and drop out at a cell face.)
    neighbours27,
    /// The paper's radius of influence R = 2*sqrt(sx^2+sy^2+sz^2) for the weights too, blending all
    /// centres whose sphere contains x (a 9x9x9 neighbourhood for cubic cells): continuous, ~10x
    /// slower to evaluate, slightly smoother.
    paper_radius,
};

struct FieldParams {
    FieldKind kind = FieldKind::rbf_grid;
    // --- Hardy's constant (section 2.1.1)
    double hardy_c_rel = 0.025;   ///< c_world = hardy_c_rel * bbox diagonal (when hardy_c_world <= 0)
    double hardy_c_world = 0;     ///< > 0: c in world units, overrides hardy_c_rel
    /// A local fit's c is at most hardy_c_spacing x its point spacing (the mean nearest-neighbour
    /// distance of its points, kernels/local_spacing.hpp): c / spacing, and with it the conditioning
    /// of the local system, stays bounded however dense the data (with the global c alone, 42 % of
    /// the MPU locals of 3 M CT samples needed a ridge). 8 leaves data up to ~10^6 uniform points in
    /// a cube at the paper's c (the smooth test functions lose accuracy with a smaller c: Franke at
    /// 1 M points 8x the RMS error with 1 x spacing). 0: every local uses the global c (the paper).
    /// MPU and RBF-grid locals (kernels/local_multiquadric_fit.hpp); the global RBF keeps the global c.
    double hardy_c_spacing = 8.0;
    /// Each local is fitted a second time with c = hardy_c_rough x its point spacing and keeps the fit
    /// with the smaller leave-one-out error (kernels/local_multiquadric_fit.hpp): the narrow c wins at
    /// sharp edges (CT: RMS error -33 % at 1 M samples, -12 % at 3 M), the wide one on smooth data.
    /// 0: one fit (ill-conditioned locals are approximated by a ridge).
    double hardy_c_rough = 1.0;
    // --- RBF grid (section 4.3)
    double binning_m = 5;         ///< binning constant m: ~points per RBF-grid cell, > 0
    RbfGridSupport rbf_grid_support = RbfGridSupport::neighbours27;
    std::uint32_t rbf_grid_max_local = 600;  ///< cap on points of one local system (nearest kept), >= 8
    std::uint32_t rbf_grid_min_local = 20;   ///< a local with fewer points takes its nearest this many, 1..max
    /// K: a local keeps the nearest max(K, points within the weight radius R_w) of its data-sphere
    /// points (so F still interpolates every point), 0 = all of them (the paper). Cost per local is
    /// cubic in its points; see kernels/rbf_grid_field.hpp for the choice of the default.
    std::uint32_t rbf_grid_local_points = 160;
    // --- MPU octree (section 5.5)
    std::uint32_t mpu_max_points = 140;  ///< N: subdivide while a node's sphere holds more, >= 8
    /// leaves with fewer points grow their sphere to this many, 1..N. With ~25 points per local fit
    /// (alpha = 0.75, N = 100 on uniform data) mpu was up to 2.5x less accurate than SciPy's
    /// multiquadric with 50 neighbours; 50 brought it to 0.6-0.9x. 70 (with N = 140 and the blend
    /// spheres below) is as accurate as that or better on the bench's Franke and Marschner-Lobb sets
    /// (RMS -26% .. +2%) and evaluates 2-3x faster; construction costs ~1.6x (bench/RESULTS-fields.md).
    std::uint32_t mpu_min_points = 70;
    double mpu_alpha = 0.75;             ///< fit sphere radius = alpha * node diagonal, > 0.5 (covers the cube)
    /// Blend (weight) sphere of a leaf: radius min(fit sphere radius, mpu_blend_alpha * node
    /// diagonal), > 0.5: it covers the leaf's cube and lies inside the fit sphere (grown or not), so a
    /// local is only blended where it was fitted (a huge value blends over the whole fit spheres,
    /// as MPU does: grown spheres then extrapolate far beyond the data). Smaller than the fit sphere, a query blends ~5 leaves instead of
    /// ~10-30 (grown leaves' spheres are large), each near its centre. 0.52-0.55 are faster still but
    /// up to 7% / 4% less accurate on Franke's function at 1M points. Not in a .mlf's params block:
    /// the fitted state carries the leaves' blend radii.
    double mpu_blend_alpha = 0.6;
    std::uint32_t mpu_max_depth = 40;    ///< octree depth limit (a deeper leaf keeps its N nearest points)
    // --- global RBF
    std::uint32_t global_max_points = 4000;  ///< refuse larger sets (dense O(n^3) solve, O(n) evaluation)
    // --- robustness
    double merge_rel = 1e-5;      ///< merge points closer than merge_rel * mean spacing (>= 0)
    /// Build the field in coordinates scaled per axis so the bounding box becomes a cube with the
    /// same diagonal (for axes in unrelated units, e.g. x,y in km and z in m). Gradients are still
    /// per world unit. hardy_c_world, when set, is then in those scaled units. Off: isotropic world
    /// metric (right for physical space).
    bool normalise_axes = false;
};

/// Hardy's c relative to the bounding-box diagonal for a level of detail of a cluster binary tree
/// built with the dissertation's max-error split order (a .mlh read as a point set,
/// kernels/cluster_lod.hpp) when none is given. Its points crowd where the values change fast, and
/// at the default 0.025 the interpolating multiquadrics overshoot far between close sibling centres.
/// Measured (meshless-bench hierarchy-rmse --hardy-c 0.025,0.003, bench/MEASURED.md "Hierarchy"): mpu
/// RMSE of error-based LODs at 1/5/15 % of the samples, 0.025 -> 0.003: silicium 91.4/95.3/36.1 ->
/// 58.8/86.6/35.9, head 392/431/332 -> 381/279/134, LIDC2 1,686/673/487 -> 39.6/25.9/25.8 (lower in 9
/// of 9 rows); volume renderings of LIDC2 LODs 9.0 -> 26.5 dB PSNR. The weighted order's levels of
/// detail spread their points evenly enough for the default c, which reconstructs them better in 12
/// of 16 rows (bench/MEASURED.md "Levels of detail that beat random samples"): lod_hardy_c_rel.
inline constexpr double kLodHardyCRel = 0.003;
/// The c of a level of detail of a tree built with the max-error split order (or not).
inline double lod_hardy_c_rel(bool max_error_order) { return max_error_order ? kLodHardyCRel : FieldParams{}.hardy_c_rel; }

/// c in world units for data with bounds [lo, hi] (see the header comment). A degenerate box (all
/// points equal) gives hardy_c_rel (as if the diagonal were 1).
inline double hardy_c_world_for(const FieldParams& p, const std::array<Vec3, 2>& bounds) {
    if (p.hardy_c_world > 0) return p.hardy_c_world;
    const double diag = norm(bounds[1] - bounds[0]);
    return p.hardy_c_rel * (diag > 0 ? diag : 1.0);
}

/// c of one local fit whose points are `spacing` apart (world or frame units, as c_global):
/// min(c_global, hardy_c_spacing x spacing), or c_global when the cap is off or the spacing unknown (0).
inline double hardy_c_local(const FieldParams& p, double c_global, double spacing) {
    if (!(p.hardy_c_spacing > 0) || !(spacing > 0)) return c_global;
    return std::min(c_global, p.hardy_c_spacing * spacing);
}

/// "rbf-grid", "mpu", "global-rbf".
inline std::string_view field_kind_name(FieldKind k) {
    switch (k) {
        case FieldKind::rbf_grid: return "rbf-grid";
        case FieldKind::mpu: return "mpu";
        case FieldKind::global_rbf: return "global-rbf";
    }
    return "?";
}

/// Inverse of field_kind_name(); false for an unknown name.
inline bool parse_field_kind(std::string_view s, FieldKind& out) {
    for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu, FieldKind::global_rbf})
        if (s == field_kind_name(k)) { out = k; return true; }
    return false;
}

/// A field build's progress: called with the local fits just finished and the locals in all, from
/// the building threads, concurrently (must be thread-safe). It observes; the field does not depend on it.
using FieldProgress = std::function<void(double done, double total)>;

/// The local fits of an mpu field shared among cooperating processes that build the same field from
/// the same points (MPI ranks, `mpirun meshless isosurface POINTS`; chapter 5's "local RBF
/// construction" of Table 5.1 done by every machine for its part): rank r fits the r-th of `ranks`
/// equal ranges of the locals (in their octree order), then `allgather` hands every rank every
/// range. The fits are independent, so every rank ends with the single-process field, bit for bit.
/// allgather: collective over the ranks; returns every rank's bytes concatenated in rank order.
struct FitShare {
    int rank = 0, ranks = 1;
    std::function<std::vector<std::byte>(std::span<const std::byte> mine)> allgather;
};

/// What happened while building a field (counts are over local interpolants unless stated).
struct FieldBuildStats {
    std::uint64_t input_points = 0;    ///< points handed in
    std::uint64_t merged_points = 0;   ///< points removed by merging near-duplicates into another
    std::uint64_t used_points = 0;     ///< distinct points after merging
    double merge_tolerance = 0;        ///< world units
    double hardy_c_world = 0;          ///< global c, world units (the most a local uses)
    std::uint64_t c_lowered = 0;       ///< locals whose c was lowered to hardy_c_spacing x their point spacing
    std::uint64_t refitted = 0;        ///< of the locals, those that kept the fit with hardy_c_rough x their spacing
    double mean_local_c = 0;           ///< mean c over the locals, world units (frame units with normalise_axes)
    std::uint64_t locals = 0;          ///< local interpolants built (1 for global-rbf)
    std::uint64_t interpolated = 0;    ///< locals solved exactly (MQ + linear, interpolating)
    std::uint64_t rank_deficient = 0;  ///< locals whose points are collinear/coplanar (polynomial part by least squares)
    std::uint64_t regularised = 0;     ///< ill-conditioned locals solved with a ridge (approximating)
    std::uint64_t linear_fallback = 0; ///< locals that fell back to a least-squares linear fit
    std::uint64_t polynomial_only = 0; ///< locals with too few points for RBF terms (constant/linear)
    std::uint64_t capped = 0;          ///< locals that kept only their nearest points (size cap)
    std::uint64_t grown = 0;           ///< locals that took extra nearest points (rbf_grid_min_local / mpu_min_points,
                                       ///< or points off a flat local's plane)
    std::uint64_t spanned = 0;         ///< of them, flat locals that took points off their plane (kernels/flat_hull.hpp)
    std::uint64_t max_local_points = 0;
    double mean_local_points = 0;
    std::array<std::int64_t, 3> grid_dims{0, 0, 0};  ///< RBF grid n_x, n_y, n_z
    std::uint64_t octree_nodes = 0;
    std::uint32_t octree_depth = 0;
    std::uint64_t memory_bytes = 0;    ///< approximate heap held by the field
    double build_seconds = 0;
};

}  // namespace meshless
