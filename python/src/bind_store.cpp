// Brick stores in the Python module (python/README.md): meshless.open_store opens a .mlb (`meshless
// convert VOLUME -o vol.mlb`, ooc/brick_store.hpp) through stream/volume_input.hpp, the one place a
// volume input is opened; Store.isosurface runs the chapter-3 graph over its active bricks
// (stream/volume_input.hpp run_isosplat_input, what `meshless isosurface vol.mlb` runs) and hands
// the points out batch by batch, in the order the command writes them, to a Python generator.
// Threads: the graph runs on a thread of its own (and its workers) with the GIL released; it
// delivers each batch's points into a queue of at most kQueued batches and waits while the queue is
// full, so memory stays the brick cache (`memory`), the batches in flight and those queued, whatever
// the store's size. The generator takes them with the GIL released while it waits. Closing the
// generator early (or dropping it) stops the graph at its next batch and joins the thread.
// Errors of the graph (a damaged brick: DataError; a read failure: OSError) are raised by the
// generator's next step, after the batches before them.
#include <pybind11/stl.h>

#include <condition_variable>
#include <deque>
#include <cmath>
#include <exception>
#include <filesystem>
#include <mutex>
#include <thread>

#include "arrays.hpp"
#include "bindings.hpp"
#include "point_arrays.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_store.hpp"
#include "stream/available_cpus.hpp"
#include "stream/stage.hpp"
#include "stream/volume_input.hpp"

namespace meshless::python {

namespace {

/// An open brick store: its path and what its header says.
struct StoreObject {
    std::string path;
    GridSpec grid;
    std::array<double, 2> range{0, 0};
    SampleType type = SampleType::u8;
};

std::unique_ptr<StoreObject> open_store(const std::string& path) {
    auto s = std::make_unique<StoreObject>();
    s->path = path;
    py::gil_scoped_release free;
    if (!is_brick_store(path)) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) throw IoError(path + ": cannot open: no such file");
        throw FormatError(path + ": not a brick store (.mlb; meshless convert VOLUME -o vol.mlb makes one)");
    }
    VolumeOpenOptions o;
    o.memory = std::uint64_t{16} << 20;  // the header and index only
    const VolumeInput in = open_volume_input(path, o);
    s->grid = in.grid();
    s->type = in.type();
    s->range = in.value_range();
    return s;
}

/// Stops the graph: thrown from the queue's consume() when the generator was closed.
struct Cancelled : std::exception {};

/// The running isosurface of a store: the graph's thread and the queue of finished batches.
class StoreIsosurface {
public:
    static constexpr std::size_t kQueued = 4;

    StoreIsosurface(const StoreObject& s, double iso, Projection mode, std::uint64_t memory, int threads) {
        VolumeOpenOptions o;
        o.memory = memory;
        o.stream = true;
        o.threads = threads;
        {
            py::gil_scoped_release free;
            in_ = std::make_unique<VolumeInput>(open_volume_input(s.path, o));  // a damaged header fails here, at the call
        }
        worker_ = std::thread([this, iso, mode, threads] {
            try {
                QueueSink sink(*this);
                const IsoSplatResult r = run_isosplat_input(*in_, iso, mode, SamplingParams{}, sink, threads, PipelineShape::fused);
                const std::lock_guard<std::mutex> lock(m_);
                result_ = r;
            } catch (const Cancelled&) {
            } catch (...) {
                const std::lock_guard<std::mutex> lock(m_);
                error_ = std::current_exception();
            }
            const std::lock_guard<std::mutex> lock(m_);
            done_ = true;
            cv_.notify_all();
        });
    }

    ~StoreIsosurface() { stop(); }

    /// The next batch's arrays, or None at the end; raises the graph's error after the batches before it.
    py::object next() {
        std::vector<PointRecord> points;
        {
            py::gil_scoped_release free;
            std::unique_lock<std::mutex> lock(m_);
            cv_.wait(lock, [this] { return !queue_.empty() || done_; });
            if (!queue_.empty()) {
                points = std::move(queue_.front());
                queue_.pop_front();
                cv_.notify_all();
            } else if (error_) {
                std::exception_ptr e = error_;
                error_ = nullptr;
                lock.unlock();
                join();
                std::rethrow_exception(e);
            } else {
                lock.unlock();
                join();
                finished_ = true;
            }
        }
        if (finished_ && points.empty()) return py::none();
        return point_arrays(std::move(points));
    }

    /// What the run counted (complete once the generator is exhausted).
    py::dict stats() const {
        const std::lock_guard<std::mutex> lock(m_);
        return py::dict(py::arg("active_cells") = result_.sampling.active_cells, py::arg("too_far") = result_.projection.too_far,
                        py::arg("flat") = result_.projection.flat, py::arg("missed") = result_.projection.missed,
                        py::arg("seconds") = result_.seconds, py::arg("done") = done_);
    }

    /// Stops the graph (at its next batch) and joins its thread; the queued batches are dropped.
    void stop() {
        py::gil_scoped_release free;
        {
            const std::lock_guard<std::mutex> lock(m_);
            cancelled_ = true;
            queue_.clear();
            cv_.notify_all();
        }
        join();
    }

private:
    class QueueSink final : public Sink {
    public:
        explicit QueueSink(StoreIsosurface& q) : q_(q) {}
        void consume(Batch&& b) override {
            if (b.points.empty()) return;
            std::unique_lock<std::mutex> lock(q_.m_);
            q_.cv_.wait(lock, [this] { return q_.queue_.size() < kQueued || q_.cancelled_; });
            if (q_.cancelled_) throw Cancelled{};
            q_.queue_.push_back(std::move(b.points));
            q_.cv_.notify_all();
        }

    private:
        StoreIsosurface& q_;
    };

    void join() {
        if (worker_.joinable()) worker_.join();
    }

    std::unique_ptr<VolumeInput> in_;
    std::thread worker_;
    mutable std::mutex m_;
    std::condition_variable cv_;
    std::deque<std::vector<PointRecord>> queue_;
    bool done_ = false, cancelled_ = false, finished_ = false;
    std::exception_ptr error_;
    IsoSplatResult result_;
};

std::unique_ptr<StoreIsosurface> store_isosurface(const StoreObject& s, double iso, const std::string& projection,
                                                  std::uint64_t memory, int threads) {
    if (!std::isfinite(iso)) throw py::value_error("iso: expected a finite number");
    Projection mode;
    if (projection == "approx") mode = Projection::approx;
    else if (projection == "exact") mode = Projection::exact;
    else if (projection == "none") mode = Projection::none;
    else throw py::value_error("projection: expected 'approx', 'exact' or 'none', got '" + projection + "'");
    if (memory < (std::uint64_t{1} << 20)) throw py::value_error("memory: expected at least 1M (the brick cache's budget)");
    if (threads < 0 || threads > 1024) throw py::value_error("threads: expected 0..1024 (0: every CPU this process may use)");
    return std::make_unique<StoreIsosurface>(s, iso, mode, memory, threads == 0 ? available_cpus() : threads);
}

}  // namespace

void bind_store(py::module_& m) {
    py::class_<StoreObject>(m, "_Store")
        .def_static("_open", &open_store, py::arg("path"))
        .def_readonly("path", &StoreObject::path)
        .def_property_readonly("dims", [](const StoreObject& s) { return py::make_tuple(s.grid.dims[0], s.grid.dims[1], s.grid.dims[2]); })
        .def_property_readonly("spacing", [](const StoreObject& s) { return py::make_tuple(s.grid.spacing[0], s.grid.spacing[1], s.grid.spacing[2]); })
        .def_property_readonly("origin", [](const StoreObject& s) { return py::make_tuple(s.grid.origin[0], s.grid.origin[1], s.grid.origin[2]); })
        .def_property_readonly("value_range", [](const StoreObject& s) { return py::make_tuple(s.range[0], s.range[1]); })
        .def_property_readonly("dtype", [](const StoreObject& s) {
            switch (s.type) {
                case SampleType::u8: return std::string("uint8");
                case SampleType::i16: return std::string("int16");
                case SampleType::u16: return std::string("uint16");
                case SampleType::f32: break;
            }
            return std::string("float32");
        })
        .def("_isosurface", &store_isosurface, py::arg("iso"), py::arg("projection"), py::arg("memory"), py::arg("threads"));
    py::class_<StoreIsosurface>(m, "_StoreIsosurface")
        .def("_next", &StoreIsosurface::next)
        .def("_stop", &StoreIsosurface::stop)
        .def_property_readonly("stats", &StoreIsosurface::stats);
}

}  // namespace meshless::python
