// Shared pieces of the commands that build a meshless field from scattered points (probe, slice,
// resample): the field options (--field --binning --max-points --alpha --hardy-c --hardy-c-world
// --support --normalise-axes), reading POINTS (one or several files: multiblock pieces), building the
// field under --threads. Evaluation is a stage graph (stream/field_evaluate_stage.hpp). Throws UsageError
// for bad options.
#pragma once
#include <memory>
#include <span>

#include "cli/args.hpp"
#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_coverage.hpp"
#include "kernels/point_set.hpp"

namespace meshless::cli {

void add_field_options(Args& a);
FieldParams field_params(const Args& a);

/// Reads the positional POINTS files (as one set) with the point-set options.
PointSet read_points_arg(const Args& a);

/// A field and where its data covers space (--max-gap; null when --max-gap 0).
struct BuiltField {
    std::unique_ptr<Field> field;
    std::unique_ptr<PointCoverage> coverage;
};

/// Builds the field with --threads workers; prints the build summary on stderr with --stats.
BuiltField build_field(const Args& a, const PointSet& points);

}  // namespace meshless::cli
