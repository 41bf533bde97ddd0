#include "stream/field_evaluate_stage.hpp"

#include "kernels/errors.hpp"

namespace meshless {

void FieldEvaluateStage::process(Batch& b) const {
    FieldQueries& q = b.query;
    q.value.resize(q.at.size());
    q.grad.assign(q.want_grad ? q.at.size() : 0, Vec3{});
    f_.evaluate(q.at, q.value, q.grad);
    if (!coverage_) return;
    const SupportCounts c = coverage_->apply(q.at, q.value, q.grad, mode_);
    uncovered_ += c.uncovered;
    clamped_ += c.clamped;
}

}  // namespace meshless
