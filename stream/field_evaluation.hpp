// A meshless field built and evaluated under a thread count, for front ends that hold their data
// in memory (the Python module; dissertation chapters 4-5 build the fields, chapter 7 looks at
// them): fit_field runs make_field (kernels/make_field.hpp) under at most `threads` workers;
// evaluate_field runs the query graph QueryListSource -> FieldEvaluateStage -> a sink that writes
// each batch's values (and gradients) into the caller's arrays, in order (one batch or fewer
// queries: one Field::evaluate on the calling thread). Each position is evaluated independently,
// so the values do not depend on the thread count.
// Units: world coordinates in, the data's values out, gradients per world unit.
// Throws what make_field throws (FormatError for unusable data: no point, fewer than 4 distinct
// positions; InvalidArgument for bad parameters); evaluate_field throws InvalidArgument when the
// output spans do not match the queries.
#pragma once
#include <memory>
#include <span>

#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_set.hpp"
#include "stream/runner.hpp"

namespace meshless {

/// make_field(points, params, stats, progress, share) with at most `threads` workers (<= 0: available_cpus()).
std::unique_ptr<Field> fit_field(const PointSet& points, const FieldParams& params, int threads, FieldBuildStats* stats = nullptr,
                                 const FieldProgress& progress = {}, const FitShare* share = nullptr);

/// value[i] (and grad[i] when grad is not empty) of `field` at at[i]. value.size() == at.size(),
/// grad empty or of at.size().
void evaluate_field(const Field& field, std::span<const Vec3> at, std::span<double> value, std::span<Vec3> grad,
                    const RunOptions& opt = {});

}  // namespace meshless
