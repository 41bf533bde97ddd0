#include "stream/runner.hpp"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_arena.h>

#include <memory>
#include <thread>

namespace meshless {

void run_pipeline(Source& source, std::span<const Stage* const> stages, Sink& sink,
                  const RunOptions& opt) {
    int threads = opt.threads;
    if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    if (threads == 1) {
        while (auto b = source.next()) {
            for (const Stage* s : stages) s->process(*b);
            sink.consume(std::move(*b));
        }
        sink.finish();
        return;
    }
    // Allow as many threads as asked for, even beyond the core count (TBB's default cap is cores).
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(threads));
    oneapi::tbb::task_arena arena(threads);
    arena.execute([&] {
        oneapi::tbb::parallel_pipeline(
            static_cast<std::size_t>(2 * threads),
            oneapi::tbb::make_filter<void, std::shared_ptr<Batch>>(
                oneapi::tbb::filter_mode::serial_in_order,
                [&](oneapi::tbb::flow_control& fc) -> std::shared_ptr<Batch> {
                    auto b = source.next();
                    if (!b) {
                        fc.stop();
                        return nullptr;
                    }
                    return std::make_shared<Batch>(std::move(*b));
                }) &
                oneapi::tbb::make_filter<std::shared_ptr<Batch>, std::shared_ptr<Batch>>(
                    oneapi::tbb::filter_mode::parallel,
                    [&](std::shared_ptr<Batch> b) {
                        for (const Stage* s : stages) s->process(*b);
                        return b;
                    }) &
                oneapi::tbb::make_filter<std::shared_ptr<Batch>, void>(
                    oneapi::tbb::filter_mode::serial_in_order,
                    [&](std::shared_ptr<Batch> b) { sink.consume(std::move(*b)); }));
    });
    sink.finish();
}

}  // namespace meshless
