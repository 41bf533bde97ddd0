// Shared preparation of a PointSet for the meshless fields (dissertation chapters 4-5): checks
// (at least one point, finite coordinates and values, matching sizes), merges near-duplicates
// within params.merge_rel x mean spacing, scales the axes when params.normalise_axes (the factors
// are returned in MergedPoints::scale: frame position = (world - origin) * scale), and fills the common FieldBuildStats entries.
// Throws FormatError naming the first offending point, InvalidArgument for bad parameters.
// Thread-safety: pure function.
#pragma once
#include <string_view>

#include "kernels/field_params.hpp"
#include "kernels/merge_near_duplicates.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

/// `who` names the caller in messages ("rbf-grid", ...).
MergedPoints prepare_field_points(const PointSet& points, const FieldParams& params, std::string_view who,
                                  FieldBuildStats* stats);

}  // namespace meshless
