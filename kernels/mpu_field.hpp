// The multi-level partition-of-unity field of dissertation section 5.5 (after Ohtake et al.'s MPU
// implicits): an octree over the points; every node has a sphere of influence centred at the node
// (cube) centre with radius alpha * d (d = the node's diagonal, alpha = 0.75); a node whose sphere
// holds more than N points (N = 100) is subdivided, so the leaves ("interpolation nodes") hold at
// most N points and each gets a local multiquadric (kernels/multiquadric.hpp) over the points in its
// sphere. The locals are blended with Franke-Nielson weights over their spheres
// (kernels/partition_of_unity.hpp); evaluation blends the leaves whose sphere holds x (see
// "Evaluation" below). Only the original points are used.
//
// Coverage: alpha > 0.5 makes every leaf's sphere contain its cube, and the leaves tile the root
// cube (the bounding box grown to a cube), so F is finite everywhere in the bounding box. A leaf
// whose sphere holds fewer than mpu_min_points points (sparse regions, empty octants) grows its
// sphere until it holds that many (counted in FieldBuildStats::grown). Outside the union of the
// spheres evaluate() gives NaN (value and gradient). A leaf at mpu_max_depth with more than N points
// keeps its N nearest (FieldBuildStats::capped). F interpolates the data: every sphere that weighs
// at a data point holds that point (up to the solver's 1e-8 residual), unless a local was capped,
// regularised or fell back.
// Evaluation: each leaf's centres are copied structure-of-arrays with its lambdas (the sum runs
// SIMD-wide, kernels/multiquadric_sum.hpp); inside the root cube a uniform lookup grid (about one
// cell per leaf) lists, per cell, the leaves whose sphere meets it, so a query tests only those
// instead of descending the tree (outside the root cube it descends the tree). Batches of >=
// kBatchOrderMin queries are evaluated lookup cell by lookup cell (kernels/batch_order.hpp) and
// written back in place: every query's bits equal its single-point result.
// Units: world in, data units out, gradient per world unit. Memory: ~N/2 points per leaf x 32 bytes
// plus the lookup lists, ~500 bytes per input point (FieldBuildStats::memory_bytes at 1M uniform). Construction: sequential octree,
// parallel fits (oneTBB; the result does not depend on the thread count); evaluate() is
// thread-safe (const).
// Throws FormatError/InvalidArgument (see make_field.hpp). save_state/load_state carry the fitted
// state (kernels/field_state.hpp) to and from a .mlf file.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/field_state.hpp"
#include "kernels/multiquadric.hpp"
#include "kernels/multiquadric_sum.hpp"
#include "kernels/partition_of_unity.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

class MpuField final : public Field {
public:
    /// progress (optional): the local fits as they finish (kernels/field_params.hpp, FieldProgress).
    MpuField(const PointSet& points, const FieldParams& params, FieldBuildStats* stats = nullptr,
             const FieldProgress& progress = {});
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override;
    std::array<Vec3, 2> bounds() const override { return bounds_; }
    std::string name() const override { return "mpu"; }

    struct LeafInfo {
        Vec3 centre;    ///< world
        double half;    ///< half edge of the node cube
        double radius;  ///< sphere of influence
    };
    /// The interpolation nodes (tests and diagnostics; half and radius in frame units, i.e. world
    /// units unless params.normalise_axes).
    std::vector<LeafInfo> leaves() const;

    /// The fitted state (kernels/field_state.hpp): the octree, the locals, their centres (each
    /// distinct point once, see put_centres) and lambdas, the lookup lists (the leaf spheres and the subtree radii are recomputed on load).
    void save_state(FieldStateWriter& w) const;
    /// A field from a saved state, validated (a proper octree of depth <= 60, every index in
    /// range); evaluates bit-identically to the saved one. FormatError through FieldState::fail.
    static std::unique_ptr<MpuField> load_state(FieldState& s);

private:
    MpuField() = default;
    struct Node {
        Vec3 c;              // centre (frame)
        double half = 0;     // half edge
        double r = 0;        // leaf: weight radius
        double rsub = 0;     // bounding radius of the spheres in the subtree
        std::int32_t child = -1;  // first of 8 children, -1 for a leaf
        std::int32_t local = -1;  // leaf: index into locals_
    };
    struct LeafSphere {
        Vec3 c;           // centre (frame)
        double r, r2;     // weight radius and its square
    };
    void build_lookup();
    void compute_subtree_radii();  // Node::rsub from the children (children follow their parent)
    void lookup_geometry();        // leaf_ and the lookup grid's g_, g_lo_, g_cell_, g_inv_
    std::uint32_t batch_key(const Vec3& world) const;  // lookup cell of a query (kernels/batch_order.hpp)
    void eval_one(const Vec3& world, double& value, Vec3* grad, PuBlend& blend) const;
    void add_leaf(std::size_t l, const Vec3& x, bool want_grad, PuBlend& blend) const;

    Vec3 origin_, scale_{1, 1, 1};  // frame = (world - origin_) * scale_
    std::array<Vec3, 2> bounds_;
    std::vector<Node> nodes_;
    std::vector<MultiquadricLocal> locals_;
    std::vector<LeafSphere> leaf_;            // per local (leaf order)
    std::vector<double> px_, py_, pz_;        // leaf l's centres: [first, first + count), leaf order
    std::vector<double> lambda_;
    // Lookup grid over the root cube: cell (i, j, k) lists the leaves whose sphere meets it.
    Vec3 g_lo_;
    double g_cell_ = 1, g_inv_ = 1;
    std::int64_t g_ = 1;
    std::vector<std::uint32_t> grid_first_;   // CSR offsets, g_^3 + 1
    std::vector<std::uint32_t> grid_leaf_;
};

}  // namespace meshless
