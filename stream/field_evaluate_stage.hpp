// The field evaluation stage (probe / slice / resample graphs): one Field::evaluate per batch of
// queries (value, and gradient when the batch wants it), then, with a PointCoverage, positions the
// data does not reach set to NaN (values there would be extrapolation). Each position is evaluated
// independently of the others, so outputs are identical for any thread count and batch size.
// Thread-safe (the field and coverage are; the masked count is an atomic). Field and coverage must
// outlive the stage. Throws FormatError on a batch that is not of kind query.
#pragma once
#include <atomic>

#include "kernels/field.hpp"
#include "kernels/point_coverage.hpp"
#include "stream/stage.hpp"

namespace meshless {

class FieldEvaluateStage final : public Stage {
public:
    FieldEvaluateStage(const Field& f, const PointCoverage* coverage = nullptr) : f_(f), coverage_(coverage) {}
    void process(Batch& b) const override;
    /// Positions set to NaN as not covered by the data.
    std::size_t uncovered() const { return masked_.load(); }

private:
    const Field& f_;
    const PointCoverage* coverage_;
    mutable std::atomic<std::size_t> masked_{0};
};

}  // namespace meshless
