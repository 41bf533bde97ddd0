// Shared preparation of a PointSet for the meshless fields (dissertation chapters 4-5): checks
// (at least one point, finite coordinates and values, matching sizes), merges near-duplicates
// within params.merge_rel x mean spacing, scales the axes when params.normalise_axes (the factors
// are returned in MergedPoints::scale: frame position = (world - origin) * scale), and fills the common FieldBuildStats entries.
// Throws FormatError naming the first offending point, or when the set is empty or has fewer than 4
// distinct points after merging near-duplicates (the data's fault); InvalidArgument for bad parameters.
// Thread-safety: pure function.
#pragma once
#include <array>
#include <string_view>

#include "kernels/field_params.hpp"
#include "kernels/field_region.hpp"
#include "kernels/merge_near_duplicates.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

/// `who` names the caller in messages ("rbf-grid", ...).
MergedPoints prepare_field_points(const PointSet& points, const FieldParams& params, std::string_view who,
                                  FieldBuildStats* stats);
/// The same for a part of a whole point set (kernels/field_region.hpp): the merge tolerance, the
/// origin, the axis scales and Hardy's c come from the whole set's `frame` (the overload above
/// passes field_frame_of(points.pos)).
MergedPoints prepare_field_points(const PointSet& points, const FieldParams& params, std::string_view who,
                                  FieldBuildStats* stats, const FieldFrame& frame);

/// A world box in m's frame: (world - m.origin) * m.scale per corner (the frame's bounding box of
/// the points inside `world`, bit for bit, when they include its extreme coordinates).
std::array<Vec3, 2> frame_box(const MergedPoints& m, const std::array<Vec3, 2>& world);

/// Reorders m.pos and m.value (together) by the Morton code of the position in the box [lo, hi]
/// (21 bits per axis; ties by the current order), so that spatially close points are close in
/// memory: the fields' neighbourhood lists and local fits then read a few runs of memory instead
/// of random addresses. Deterministic (independent of the thread count); parallel (oneTBB).
void morton_order_points(MergedPoints& m, const Vec3& lo, const Vec3& hi);

}  // namespace meshless
