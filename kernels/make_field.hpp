// Factory for the meshless fields of dissertation chapters 4-5 (params.kind):
//   rbf-grid   kernels/rbf_grid_field.hpp   (section 4.3)
//   mpu        kernels/mpu_field.hpp        (section 5.5)
//   global-rbf kernels/global_rbf_field.hpp (section 2.1.1; at most params.global_max_points points)
// The returned field does not reference `points` (it keeps its own merged copy).
// Preconditions: at least 4 distinct points (fewer: FormatError "…N distinct points …, at least 4 are needed").
// Throws FormatError for non-finite coordinates/values or mismatched sizes (naming the point),
// InvalidArgument for bad parameters (an mpu alpha outside (0.5, kMaxMpuAlpha] among them) or an
// oversized global-rbf set. stats (optional) receives counts
// of merged points, local outcomes (regularised, fallbacks, rank-deficient), sizes, memory and the
// wall-clock build time. Construction uses oneTBB (limit it with tbb::global_control); the result
// does not depend on the thread count. A fitted field is saved and loaded again, evaluating
// bit-identically, through kernels/field_state.hpp (save_field_state / load_field_state; the
// .mlf file of formats/field_file.hpp).
#pragma once
#include <memory>

#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

/// The largest mpu sphere factor (FieldParams::mpu_alpha, in (0.5, kMaxMpuAlpha]): a sphere of alpha x
/// the node diagonal holds about (alpha sqrt 3)^3 x the points of its cube, so the octree keeps
/// subdividing until its leaves are about alpha sqrt 3 times smaller, and its leaves, their points
/// and the fits grow as alpha^3 (alpha 100 on 197 points took gigabytes).
inline constexpr double kMaxMpuAlpha = 4.0;

/// A lower estimate of the bytes an mpu octree over n points takes (its leaves' point lists, the
/// fits' coefficients and the nodes; kernels/mpu_field.cpp): leaves ~ max(1, (alpha sqrt 3)^3 n / N)
/// of up to N points, 12 bytes per point of a leaf and 128 per leaf. Saturates at UINT64_MAX.
std::uint64_t mpu_octree_bytes_estimate(std::uint64_t n, const FieldParams& params);

/// progress (optional): the local fits of rbf-grid and mpu as they finish (FieldProgress; global-rbf
/// is one solve and reports nothing).
/// share (optional): the mpu fits shared among ranks (FieldParams' FitShare; every rank must call
/// make_field with the same points and params); other kinds are built whole on every rank.
std::unique_ptr<Field> make_field(const PointSet& points, const FieldParams& params, FieldBuildStats* stats = nullptr,
                                  const FieldProgress& progress = {}, const FitShare* share = nullptr);

}  // namespace meshless
