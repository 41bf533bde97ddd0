#include "stream/runner.hpp"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_arena.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "stream/available_cpus.hpp"

namespace meshless {

namespace {

/// Record arrays of consumed batches, handed to new batches so that their capacity is reused: a
/// steady-state run allocates (and page-faults) no new batch memory. At most `cap` arrays of each
/// kind are kept, so the pool holds no more than the batches that were in flight at once.
/// Thread-safe (the runner's first and last filters may run at the same time).
class BufferPool {
public:
    explicit BufferPool(std::size_t cap) : cap_(cap) {}
    /// Gives a new batch spare arrays where it has none.
    void refill(Batch& b) {
        std::lock_guard lock(m_);
        if (b.points.capacity() == 0 && !points_.empty()) {
            b.points.swap(points_.back());
            points_.pop_back();
        }
        if (b.samples.capacity() == 0 && !samples_.empty()) {
            b.samples.swap(samples_.back());
            samples_.pop_back();
        }
    }
    /// Takes back what the sink left in a consumed batch (a sink may have moved the arrays out).
    void reclaim(Batch& b) {
        std::lock_guard lock(m_);
        if (b.points.capacity() != 0 && points_.size() < cap_) {
            b.points.clear();
            points_.push_back(std::move(b.points));
        }
        if (b.samples.capacity() != 0 && samples_.size() < cap_) {
            b.samples.clear();
            samples_.push_back(std::move(b.samples));
        }
    }

private:
    std::mutex m_;
    std::size_t cap_;
    std::vector<std::vector<PointRecord>> points_;
    std::vector<std::vector<SampleRecord>> samples_;
};

/// Throws GraphError when a batch reaching the sink is not of the payload the graph declared.
void check_delivered(const Batch& b, Payload declared, const Source& source, std::span<const Stage* const> stages) {
    if (declared == Payload::cells ? b.count() == 0 : b.kind == record_kind_of(declared)) return;
    const std::string last = stages.empty() ? graph_node_name(typeid(source)) : [&] {
        const Stage& stage = *stages.back();
        return graph_node_name(typeid(stage));
    }();
    throw GraphError("stage graph: " + last + " delivered batch " + std::to_string(b.seq) + " tagged " +
                     payload_name(payload_of(b.kind)) + ", it declared " + payload_name(declared));
}

}  // namespace

void run_pipeline(Source& source, std::span<const Stage* const> stages, Sink& sink,
                  const RunOptions& opt) {
    const Payload declared = check_graph(source, stages, sink);
    int threads = opt.threads;
    if (threads <= 0) threads = available_cpus();
    if (threads == 1) {
        BufferPool pool(1);
        while (auto b = source.next()) {
            pool.refill(*b);
            for (const Stage* s : stages) s->process(*b);
            check_delivered(*b, declared, source, stages);
            sink.consume(std::move(*b));
            if (!source.recycle(*b)) pool.reclaim(*b);
        }
        sink.finish();
        return;
    }
    const std::size_t tokens = static_cast<std::size_t>(2 * threads);
    BufferPool pool(tokens);
    // Allow as many threads as asked for, even beyond the core count (TBB's default cap is cores).
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(threads));
    oneapi::tbb::task_arena arena(threads);
    // The batches in flight live here, not in TBB's filter buffers: when a stage or the sink throws,
    // TBB cancels the pipeline without destroying the items it holds between filters (LeakSanitizer
    // caught it under `ulimit -f`), while these are destroyed with the vector. Tokens bound the
    // batches in flight, so a free slot is always there when the input filter runs.
    std::vector<Batch> slots(tokens);
    std::vector<Batch*> free_slots;
    for (Batch& b : slots) free_slots.push_back(&b);
    std::mutex free_mutex;
    arena.execute([&] {
        oneapi::tbb::parallel_pipeline(
            tokens,
            oneapi::tbb::make_filter<void, Batch*>(
                oneapi::tbb::filter_mode::serial_in_order,
                [&](oneapi::tbb::flow_control& fc) -> Batch* {
                    auto b = source.next();
                    if (!b) {
                        fc.stop();
                        return nullptr;
                    }
                    Batch* p = nullptr;
                    {
                        std::lock_guard lock(free_mutex);
                        p = free_slots.back();
                        free_slots.pop_back();
                    }
                    *p = std::move(*b);
                    pool.refill(*p);
                    return p;
                }) &
                oneapi::tbb::make_filter<Batch*, Batch*>(
                    oneapi::tbb::filter_mode::parallel,
                    [&](Batch* b) {
                        for (const Stage* s : stages) s->process(*b);
                        return b;
                    }) &
                oneapi::tbb::make_filter<Batch*, void>(
                    oneapi::tbb::filter_mode::serial_in_order,
                    [&](Batch* b) {
                        check_delivered(*b, declared, source, stages);
                        sink.consume(std::move(*b));
                        if (!source.recycle(*b)) pool.reclaim(*b);
                        std::lock_guard lock(free_mutex);
                        free_slots.push_back(b);
                    }));
    });
    sink.finish();
}

}  // namespace meshless
