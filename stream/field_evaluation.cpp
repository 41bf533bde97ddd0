#include "stream/field_evaluation.hpp"

#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <vector>

#include "kernels/errors.hpp"
#include "kernels/make_field.hpp"
#include "stream/available_cpus.hpp"
#include "stream/field_evaluate_stage.hpp"
#include "stream/field_query_sources.hpp"

namespace meshless {

namespace {

/// Copies each evaluated batch into the caller's arrays (batches arrive in sequence order).
class SpanSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::queries; }
    SpanSink(std::span<double> value, std::span<Vec3> grad) : value_(value), grad_(grad) {}
    void consume(Batch&& b) override {
        const FieldQueries& q = b.query;
        std::copy(q.value.begin(), q.value.end(), value_.begin() + static_cast<std::ptrdiff_t>(at_));
        if (!grad_.empty()) std::copy(q.grad.begin(), q.grad.end(), grad_.begin() + static_cast<std::ptrdiff_t>(at_));
        at_ += q.value.size();
    }

private:
    std::span<double> value_;
    std::span<Vec3> grad_;
    std::size_t at_ = 0;
};

int worker_count(int threads) { return threads > 0 ? threads : available_cpus(); }

}  // namespace

std::unique_ptr<Field> fit_field(const PointSet& points, const FieldParams& params, int threads, FieldBuildStats* stats,
                                 const FieldProgress& progress, const FitShare* share) {
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(worker_count(threads)));
    return make_field(points, params, stats, progress, share);
}

void evaluate_field(const Field& field, std::span<const Vec3> at, std::span<double> value, std::span<Vec3> grad,
                    const RunOptions& opt) {
    if (value.size() != at.size() || (!grad.empty() && grad.size() != at.size()))
        throw InvalidArgument("evaluate_field: the output arrays must hold one entry per query");
    if (at.empty()) return;
    if (at.size() <= kQueriesPerBatch) {  // one batch: on this thread, without the graph's start-up
        std::vector<Vec3> g(grad.empty() ? 0 : at.size());
        field.evaluate(at, value, g);
        std::copy(g.begin(), g.end(), grad.begin());
        return;
    }
    QueryListSource source(std::vector<Vec3>(at.begin(), at.end()), !grad.empty());
    const FieldEvaluateStage evaluate(field);
    SpanSink sink(value, grad);
    const Stage* stages[] = {&evaluate};
    run_pipeline(source, stages, sink, {worker_count(opt.threads)});
}

}  // namespace meshless
