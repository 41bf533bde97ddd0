// The RBF-grid partition of unity of dissertation section 4.3: scattered (or multiblock, with the
// connectivity dropped) points binned into a near-cubic regular "RBF grid" over their bounding box,
//     s = (m wx wy wz / n)^(1/3),  n_x = max(1, round(wx / s)), ...,  s_x = wx / n_x, ...
// (m = binning constant, ~points per cell; an axis whose extent is below s/2 gets one cell and s is
// recomputed over the other axes, so flat or thin data still gets ~m points per cell). Every cell
// whose 27-cell neighbourhood holds a point inside the sphere of radius R = 2 sqrt(sx^2+sy^2+sz^2)
// around its centre gets a local multiquadric (kernels/multiquadric.hpp) over exactly those points
// (the paper: "if this region happens to be empty, we do not construct an RBF center"). A local with
// fewer than rbf_grid_min_local (20) such points takes its nearest 20 from a widening neighbourhood
// instead (sparse regions: 1-3 points cannot determine the linear part; counted as "grown").
// A local whose points are coplanar or collinear (kernels/flat_hull.hpp: layered data, a
// curvilinear grid whose planes lie farther apart than the cells, such as the blunt fin's x-planes
// 1.5-3.5 units apart with cells of 0.55) keeps its points and adds the nearest max(4, 10) points off
// their plane or line, from a widening neighbourhood (also counted as "grown"): its linear part is
// then determined across the plane, so F reproduces linear data between the layers (before, such a
// local's rank-3 linear part was regularised and F was a step function between them).
// Nearest-K rule (FieldParams::rbf_grid_local_points, K, default 160; 0 = the paper's "all"): a
// local keeps the nearest max(K, points within its weight radius R_w) of those points. It keeps
// every point its weight reaches, so F still interpolates the data; it only trims over-full locals
// of non-uniform data, whose cost is cubic in their points. K = 160 is ~1.2x the 27 m = 135 points
// of a local on uniform data (m = 5), so uniform data is left as it was (the accuracy table of
// bench/RESULTS-fields.md is unchanged to the printed digits), while on the combustor's graded
// curvilinear nodes the mean local shrinks from 184 points (max 483) to 128 (max 236) and the fit
// takes 1/3 of the CPU time. K = 50 (SciPy's neighbors) was measured too: 5x faster on uniform data
// but 2.2x the RMS error on Franke's function at 10K points, so not the default. A local with more
// than rbf_grid_max_local (600) points even so keeps its nearest 600 (counted as "capped": only
// then can F miss a data point, e.g. a dense cluster of thousands of points inside one cell).
// Evaluation blends the locals with Franke-Nielson weights (kernels/partition_of_unity.hpp).
//
// Continuity. The paper evaluates the 27 neighbouring locals with weight radius R. A centre two
// cells away is then still within R of x but left out, so F jumps at cell faces. Here the weight
// radius R_w and the evaluated neighbourhood are matched so that every centre with a non-zero
// weight at x is evaluated (F is continuous, C^1 away from centres):
//   RbfGridSupport::neighbours27 (default): R_w = 1.5 x min{s_d : n_d >= 3} (at least 1.01 x the
//     half cell diagonal, at most R), usually exactly the 27 neighbouring cells;
//   RbfGridSupport::paper_radius: R_w = R, with a neighbourhood of ceil(R/s_d - 1/2) cells per axis.
// With neighbours27 every local that weighs at a data point contains that point, so F interpolates
// the data (up to the solver's 1e-8 residual), unless a local was capped, regularised or fell back.
//
// Coverage: F is defined (finite) where some local's weight sphere contains x: every cell with a
// data point within its 27 neighbours, i.e. the whole bounding box for evenly spread data. Elsewhere
// evaluate() gives NaN (value and gradient). Units: world in, data units out, gradient per world unit.
//
// Evaluation layout: the points are stored once, sorted by cell, structure-of-arrays; a local over
// its 27-cell block (the data sphere always contains the whole block) reads them as up to 9 runs,
// one per (y, z) row of the block, with its lambdas contiguous in the same order, so there is no
// per-centre index and the sum runs SIMD-wide (kernels/multiquadric_sum.hpp). Grown or capped
// locals get their own copied run. A query visits only the cells whose centre lies within R_w on
// every axis, selects (branch-free) those within R_w, and sums them in one multiquadric_sums() call.
// Batches of >= kBatchOrderMin queries are evaluated cell by cell in Morton order (kernels/
// batch_order.hpp) and written back in place: every query's bits equal its single-point result.
// Memory: ~27 m lambdas per local x 8 bytes + 24 bytes per point: ~1.1 KB per cell at m = 5
// (~260 bytes per input point). Construction is parallel (oneTBB parallel_for over cells; the
// result does not depend on the thread count); evaluate() is thread-safe (const). Throws
// FormatError/InvalidArgument (see make_field.hpp). save_state/load_state carry the fitted state
// (kernels/field_state.hpp) to and from a .mlf file.
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

class RbfGridField final : public Field {
public:
    /// progress (optional): the local fits as they finish (kernels/field_params.hpp, FieldProgress).
    RbfGridField(const PointSet& points, const FieldParams& params, FieldBuildStats* stats = nullptr,
                 const FieldProgress& progress = {});
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override;
    std::array<Vec3, 2> bounds() const override { return bounds_; }
    std::string name() const override { return "rbf-grid"; }

    std::array<std::int64_t, 3> dims() const { return {n_[0], n_[1], n_[2]}; }
    /// Cell edges, world units.
    Vec3 cell_size() const { return {s_.x / scale_.x, s_.y / scale_.y, s_.z / scale_.z}; }
    /// World position of the grid's lower corner.
    Vec3 grid_lo() const { return Vec3{lo_.x / scale_.x, lo_.y / scale_.y, lo_.z / scale_.z} + origin_; }
    double data_radius() const { return r_data_; }   ///< R = 2 |s| (frame units: world unless normalise_axes)
    double weight_radius() const { return r_w_; }    ///< R_w (partition-of-unity support, frame units)
    std::size_t local_count() const { return locals_.size(); }

    /// The fitted state (kernels/field_state.hpp): every array evaluate() reads.
    void save_state(FieldStateWriter& w) const;
    /// A field from a saved state, validated (sizes, indices, derived scalars recomputed bit for
    /// bit); evaluates bit-identically to the saved one. FormatError through FieldState::fail.
    static std::unique_ptr<RbfGridField> load_state(FieldState& s);

private:
    RbfGridField() = default;
    std::uint32_t batch_key(const Vec3& world) const;  // cell of a query (kernels/batch_order.hpp)
    // Per-evaluate() scratch: the locals weighing at the query (in blend order), their cell
    // centres, distances, terms and multiquadric sums.
    struct EvalScratch {
        std::vector<std::int32_t> local;
        std::vector<Vec3> centre;
        std::vector<double> dist;
        std::vector<MqLocalTerms> terms;
        std::vector<MqSum> sums;
    };
    void eval_one(const Vec3& world, double& value, Vec3* grad, PuBlend& blend, EvalScratch& sc) const;

    Vec3 origin_, scale_{1, 1, 1};  // frame = (world - origin_) * scale_                 // world position of the frame of pos_
    std::array<Vec3, 2> bounds_;
    Vec3 lo_, s_, inv_s_;         // grid lower corner (frame), cell edges, 1/edge (0 on 1-cell axes)
    std::int64_t n_[3] = {1, 1, 1};
    double reach_[3] = {0, 0, 0};  // R_w / s_a (0 on 1-cell axes)
    double r_data_ = 0, r_w_ = 0;
    std::vector<double> px_, py_, pz_;           // points sorted by cell, then copies for grown/capped locals
    std::vector<std::int32_t> cell_local_;       // cell -> local index or -1
    std::vector<MultiquadricLocal> locals_;
    std::vector<std::uint32_t> run_first_;       // local l reads runs_[run_first_[l] .. run_first_[l + 1])
    std::vector<MqRun> runs_;
    std::vector<double> lambda_;                 // local l: lambda_[first .. first + count), in run order
};

}  // namespace meshless
