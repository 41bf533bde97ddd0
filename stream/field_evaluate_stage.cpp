#include "stream/field_evaluate_stage.hpp"

#include "kernels/errors.hpp"

namespace meshless {

void FieldEvaluateStage::process(Batch& b) const {
    if (b.kind != RecordKind::query) throw FormatError("field evaluation: expected query positions");
    FieldQueries& q = b.query;
    q.value.resize(q.at.size());
    q.grad.assign(q.want_grad ? q.at.size() : 0, Vec3{});
    f_.evaluate(q.at, q.value, q.grad);
    if (coverage_) masked_ += coverage_->mask(q.at, q.value, q.grad);
}

}  // namespace meshless
