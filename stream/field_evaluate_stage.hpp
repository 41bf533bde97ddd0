// The field evaluation stage (probe / slice / resample graphs): one Field::evaluate per batch of
// queries (value, and gradient when the batch wants it), then, with a PointCoverage, the support
// test and value band of kernels/point_coverage.hpp: positions the data does not reach handled per
// Extrapolate (NaN by default: values there would be extrapolation), values kept within the data
// range around them (when the coverage has the data values). Each position is evaluated
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
    PayloadSet takes() const override { return Payload::queries; }
    Payload gives(Payload) const override { return Payload::queries; }
    FieldEvaluateStage(const Field& f, const PointCoverage* coverage = nullptr, Extrapolate mode = Extrapolate::nan)
        : f_(f), coverage_(coverage), mode_(mode) {}
    void process(Batch& b) const override;
    /// Positions outside the data's support (NaN under Extrapolate::nan).
    std::size_t uncovered() const { return uncovered_.load(); }
    /// Values moved into their band (kernels/point_coverage.hpp).
    std::size_t clamped() const { return clamped_.load(); }

private:
    const Field& f_;
    const PointCoverage* coverage_;
    Extrapolate mode_;
    mutable std::atomic<std::size_t> uncovered_{0}, clamped_{0};
};

}  // namespace meshless
