// The multi-level partition-of-unity field of dissertation section 5.5 (after Ohtake et al.'s MPU
// implicits): an octree over the points; every node has a sphere of influence centred at the node
// (cube) centre with radius alpha * d (d = the node's diagonal, alpha = 0.75); a node whose sphere
// holds more than N points (N = 140) is subdivided, so the leaves ("interpolation nodes") hold at
// most N points and each gets a local multiquadric (kernels/multiquadric.hpp) over the points of its
// blend sphere (below), or its nearest mpu_min_points (70) when the blend sphere holds fewer (the fit
// sphere): a fit then costs about the same at any density (fitting the whole MPU sphere took up to
// N points, 8x the work, and its points beyond the blend sphere never weigh). Each local's Hardy c
// is the global one capped at hardy_c_spacing x the mean nearest-neighbour distance of its points
// (kernels/field_params.hpp), so dense data stays well conditioned. The locals are blended with Franke-Nielson weights
// (kernels/partition_of_unity.hpp) over blend spheres of radius blend_alpha * d (0.6; at most the
// fit sphere): each covers its cube and lies inside the fit sphere, so a local weighs only where
// it was fitted, and a query blends ~5 leaves, each near its centre (MPU's own blend sphere is its
// fit sphere; with grown leaves that made 10-30 overlapping locals per query, slower and no more
// accurate: FieldParams::mpu_blend_alpha). Evaluation blends the leaves whose blend sphere holds x
// (see "Evaluation" below). Only the original points are used.
//
// Coverage: blend_alpha > 0.5 makes every leaf's blend sphere contain its cube, and the leaves tile
// the root cube (the bounding box grown to a cube), so F is finite everywhere in the bounding box. A
// leaf whose fit sphere holds fewer than mpu_min_points points (70; sparse regions, empty octants)
// grows it until it holds that many (counted in FieldBuildStats::grown); a leaf whose points are
// coplanar or collinear (kernels/flat_hull.hpp: layers farther apart than the leaves) also takes the
// nearest max(4, 35) points off their plane or line from its nearest ancestor holding them (also
// counted as grown), so that its linear part is determined across it. Outside the union of the
// blend spheres evaluate() gives NaN (value and gradient). A leaf at mpu_max_depth with more than N
// points keeps its N nearest (FieldBuildStats::capped). F interpolates the data: every local that
// weighs at a data point was fitted to that point (up to the solver's 1e-8 residual), unless a
// local was capped, regularised or fell back.
// Evaluation: each leaf's centres are copied structure-of-arrays with its lambdas (the sum runs
// SIMD-wide, kernels/multiquadric_sum.hpp); inside the root cube a uniform lookup grid (about 16
// cells per leaf) lists, per cell, the leaves whose blend sphere meets it, so a query tests only
// those (branch-free; ~2-3x the ~5 it blends) instead of descending the tree (outside the root cube it descends the tree),
// then sums the selected leaves in one multiquadric_sums() call. Batches of >= kBatchOrderMin
// queries are evaluated lookup cell by lookup cell in Morton order (kernels/batch_order.hpp) and
// written back in place: every query's bits equal its single-point result.
// Units: world in, data units out, gradient per world unit. Memory: ~mpu_min_points (70) points per
// leaf x 32 bytes plus the lookup lists, ~730 bytes per input point (FieldBuildStats::memory_bytes
// at 1M uniform, ~90 of them the lookup lists; 500 with 50-point fits and a coarser lookup). Construction: the octree parallel by subtrees (built in
// the order of a sequential depth-first build),
// parallel fits (oneTBB; the result does not depend on the thread count); evaluate() is
// thread-safe (const).
// Throws FormatError/InvalidArgument (see make_field.hpp). save_state/load_state carry the fitted
// state (kernels/field_state.hpp) to and from a .mlf file.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/field_region.hpp"
#include "kernels/mpu_fit_cache.hpp"
#include "kernels/field_state.hpp"
#include "kernels/multiquadric.hpp"
#include "kernels/multiquadric_sum.hpp"
#include "kernels/partition_of_unity.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

class MpuField final : public Field {
public:
    /// progress (optional): the local fits as they finish (kernels/field_params.hpp, FieldProgress).
    /// share (optional): fit only this rank's range of the locals and gather the others' (FitShare).
    /// region (optional): `points` are the whole set's points inside region->loaded; the octree is
    /// built in the whole set's frame and only where a leaf can weigh at a point of region->query
    /// (the other subtrees are pruned: no local), so evaluate() there gives the whole set's field's
    /// bits as long as region_exact() (kernels/field_region.hpp).
    /// cache (optional, a region build without share): copy the fits an earlier region of the same
    /// run kept for leaves with the same cube and list, and keep this one's for the next
    /// (kernels/mpu_fit_cache.hpp); the field's bits do not change.
    /// Throws FormatError when the gathered bytes do not hold the other ranks' ranges.
    MpuField(const PointSet& points, const FieldParams& params, FieldBuildStats* stats = nullptr,
             const FieldProgress& progress = {}, const FitShare* share = nullptr, const FieldRegion* region = nullptr,
             MpuFitCache* cache = nullptr);
    /// A region build: whether every point list it read (a leaf's sphere; the ancestors a grown or
    /// flat leaf searched) lay inside the loaded box. When false the build stopped before the local
    /// fits (evaluate() throws InvalidArgument) and the caller loads the lacking balls and builds
    /// again. Always true for a whole-set build.
    bool region_exact() const { return region_exact_; }
    /// A region build whose field would take more than region->max_field_bytes: it stopped before
    /// the local fits (evaluate() throws InvalidArgument); stats->memory_bytes says how much.
    bool over_budget() const { return over_budget_; }
    /// A region build: the octree nodes pruned (their subtrees weigh at no query).
    std::uint64_t pruned_nodes() const { return pruned_; }
    /// A region build that was not exact: the world balls (centre, radius) whose points a decision
    /// or a list needed and lacked (load them and build again).
    const std::vector<std::pair<Vec3, double>>& lacking_balls() const { return lacking_; }
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override;
    std::array<Vec3, 2> bounds() const override { return bounds_; }
    std::string name() const override { return "mpu"; }

    struct LeafInfo {
        Vec3 centre;    ///< world
        double half;    ///< half edge of the node cube
        double radius;  ///< blend sphere (where the local weighs)
    };
    /// The interpolation nodes, indexed by local (tests and diagnostics; half and radius in frame
    /// units, i.e. world units unless params.normalise_axes; radius: the blend sphere's).
    std::vector<LeafInfo> leaves() const;
    /// The leaves (indices into leaves()) whose blend sphere holds the world point x, in the order
    /// evaluate() blends them (ascending), as the lookup grid or the tree descent finds them (tests).
    std::vector<std::uint32_t> blended_leaves(const Vec3& world) const;
    /// The number of multiquadric terms evaluate() sums at the world point x: the centres of the
    /// blended_leaves(x) locals (diagnostics: the bench's evaluation ceiling; 0 outside every sphere).
    std::uint64_t terms_at(const Vec3& world) const;

    /// The fitted state (kernels/field_state.hpp): the octree, the locals, their centres (each
    /// distinct point once, see put_centres) and lambdas, and the lookup lists of a grid of about
    /// one cell per leaf (file version 1's; the leaf spheres and the subtree radii are recomputed
    /// on load). Throws InvalidArgument when those lists would be too large (a field loaded from a
    /// hostile file whose spheres are far larger than their leaves).
    void save_state(FieldStateWriter& w) const;
    /// A field from a saved state, validated (a proper octree of depth <= 60, every index in
    /// range, the stored lookup lists well formed); the finer lookup grid evaluation uses is then
    /// built from the leaf spheres (a coarser one when the spheres are huge, so that a hostile file
    /// costs at most ~128 x (cells + leaves) work); evaluates bit-identically to the saved one.
    /// FormatError through FieldState::fail.
    static std::unique_ptr<MpuField> load_state(FieldState& s);

private:
    MpuField() = default;
    struct Node {
        Vec3 c;              // centre (frame)
        double half = 0;     // half edge
        double r = 0;        // leaf: blend (weight) radius
        double rsub = 0;     // bounding radius of the spheres in the subtree
        std::int32_t child = -1;  // first of 8 children, -1 for a leaf
        std::int32_t local = -1;  // leaf: index into locals_
    };
    struct LeafSphere {
        Vec3 c;           // centre (frame)
        double r, r2;     // weight radius and its square
    };
    // FitShare: hands this rank's fits to the others and takes theirs (locals_, lambda_, outcomes).
    void gather_fits(const FitShare& share, const std::function<std::pair<std::size_t, std::size_t>(int)>& range_of,
                     std::vector<MultiquadricOutcome>& outcome, std::vector<std::uint8_t>& rank_def);
    void build_lookup();  // the evaluation grid: lookup_geometry and the lists at kLookupCellsPerLeaf
    int lookup_level(std::size_t per_leaf_cells) const;  // the finest grid with <= per_leaf_cells x leaves cells
    // lists of the g^3 grid over the root cube (g_lo_ set): per cell, the leaves whose sphere meets it
    // (InvalidArgument when the spheres' boxes cover more than kLookupWorkPerCell x (cells + leaves)
    // cells of that grid, or 2^32: build_lookup picks a grid where they do not)
    void lookup_lists(std::int64_t g, std::vector<std::uint32_t>& first, std::vector<std::uint32_t>& list) const;
    std::uint64_t lookup_work(std::int64_t g) const;  // cells the leaf spheres' boxes cover in a g^3 grid
    void compute_subtree_radii();  // Node::rsub from the children (children follow their parent)
    void lookup_geometry(int level);  // leaf_ and the lookup grid's g_, g_lo_, g_cell_, g_inv_ (2^level a side)
    std::uint32_t batch_key(const Vec3& world) const;  // lookup cell of a query (kernels/batch_order.hpp)
    // Per-evaluate() scratch: the leaves whose sphere holds the query (in blend order), their
    // squared distances (then distances), runs and multiquadric sums.
    struct EvalScratch {
        std::vector<std::uint32_t> leaf;
        std::vector<double> dist;
        std::vector<MqRun> runs;
        std::vector<MqLocalTerms> terms;
        std::vector<MqSum> sums;
        void clear() {
            leaf.clear();
            dist.clear();
        }
    };
    void eval_one(const Vec3& world, double& value, Vec3* grad, PuBlend& blend, EvalScratch& sc) const;
    void find_leaves(const Vec3& x, EvalScratch& sc) const;  // the leaves whose sphere holds x (frame) into sc
    void add_leaf(std::size_t l, const Vec3& x, EvalScratch& sc) const;  // selects leaf l when its sphere holds x
    void select_leaves(const std::uint32_t* cand, std::size_t n, const Vec3& x, EvalScratch& sc) const;  // the same for n
    void blend_leaves(const Vec3& x, bool want_grad, EvalScratch& sc, PuBlend& blend) const;

    bool region_ = false, region_exact_ = true, over_budget_ = false;  // built over a region (kernels/field_region.hpp); its lists whole
    std::uint64_t pruned_ = 0;
    std::vector<std::pair<Vec3, double>> lacking_;
    Vec3 origin_, scale_{1, 1, 1};  // frame = (world - origin_) * scale_
    std::array<Vec3, 2> bounds_;
    std::vector<Node> nodes_;
    std::vector<MultiquadricLocal> locals_;
    std::vector<LeafSphere> leaf_;            // per local (leaf order)
    std::vector<double> px_, py_, pz_;        // leaf l's centres: [first, first + count), leaf order
    std::vector<double> lambda_;
    // Lookup grid over the root cube: cell (i, j, k) lists the leaves whose sphere meets it. About
    // kLookupCellsPerLeaf cells per leaf: a cell then lists ~2-3x the leaves a query blends (with
    // one cell per leaf, as a .mlf stores it, ~6x: testing them was a fifth of an evaluation).
    static constexpr std::size_t kLookupCellsPerLeaf = 16;
    static constexpr std::uint64_t kLookupWorkPerCell = 128;  // build_lookup's bound on the lists' size
    Vec3 g_lo_;
    double g_cell_ = 1, g_inv_ = 1;
    std::int64_t g_ = 1;
    std::vector<std::uint32_t> grid_first_;   // CSR offsets, g_^3 + 1
    std::vector<std::uint32_t> grid_leaf_;
};

}  // namespace meshless
