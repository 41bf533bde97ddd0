// Stores in the Python module (python/README.md), opened by meshless.open_store:
// - a brick store (.mlb, `meshless convert VOLUME -o vol.mlb`, ooc/brick_store.hpp) through
//   stream/volume_input.hpp, the one place a volume input is opened; its isosurface is the chapter-3
//   graph over its active bricks (run_isosplat_input, what `meshless isosurface vol.mlb` runs);
// - a sample store (.mls, `meshless convert vol.mlb -o vol.mls`, ooc/sample_store.hpp): paradigm (A)
//   of section 3.5, its candidate rows from the span-space index (stream/sample_store_source.hpp,
//   run_isosplat_sample_store, what `meshless isosurface vol.mls` runs: the .mlb's points);
// - a point store (.mlc, `meshless convert POINTS -o pts.mlc`, formats/point_store.hpp): its bricks
//   one by one (bricks()), and the scattered isosurface of chapter 5 slab by slab within a memory
//   budget (stream/scattered_store_isosurface.hpp plan_scattered_store and
//   run_scattered_store_isosurface, the recipe `meshless isosurface pts.mlc --memory M` runs), and
//   its field at given positions slab by slab (stream/store_field_queries.hpp, `meshless probe pts.mlc`).
// Isosurfaces are handed out batch by batch, in the order the command writes them, to a Python
// generator. Threads: the graph runs on a thread of its own (and its workers) with the GIL
// released; it delivers each batch's points into a queue of at most kQueued batches and waits while
// the queue is full, so memory stays the store's budget (brick cache, slab), the batches in flight
// and those queued, whatever the store's size. The generator takes them with the GIL released while
// it waits. Closing the generator early (or dropping it) stops the graph at its next batch and joins
// the thread. Errors of the graph (a damaged brick: DataError; a read failure: OSError) are raised
// by the generator's next step, after the batches before them.
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
#include "formats/point_store.hpp"
#include "iso_params.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/sample_store.hpp"
#include "stream/available_cpus.hpp"
#include "stream/sample_store_source.hpp"
#include "stream/scattered_store_isosurface.hpp"
#include "stream/stage.hpp"
#include "stream/store_field_queries.hpp"
#include "stream/volume_input.hpp"

namespace meshless::python {

namespace {

enum class StoreKind { brick, sample, point };

/// An open store: its path and what its header says.
struct StoreObject {
    std::string path;
    StoreKind kind = StoreKind::brick;
    GridSpec grid;                       ///< brick and sample stores
    std::array<double, 2> range{0, 0};
    SampleType type = SampleType::u8;
    PointStoreInfo points;               ///< point stores
    std::shared_ptr<const PointStore> point_store;
};

std::unique_ptr<StoreObject> open_store(const std::string& path) {
    auto s = std::make_unique<StoreObject>();
    s->path = path;
    py::gil_scoped_release free;
    if (is_sample_store(path)) {
        const auto st = SampleStore::open(path);
        s->kind = StoreKind::sample;
        s->grid = st->info().grid;
        s->type = st->info().type;
        s->range = {st->info().value_lo, st->info().value_hi};
        return s;
    }
    if (is_point_store(path)) {
        s->kind = StoreKind::point;
        s->point_store = PointStore::open(path);
        s->points = s->point_store->info();
        s->range = {s->points.value_min, s->points.value_max};
        return s;
    }
    if (!is_brick_store(path)) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) throw IoError(path + ": cannot open: no such file");
        throw FormatError(path + ": not a store (a brick store .mlb, sample store .mls or point store .mlc; "
                                 "meshless convert makes them)");
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

    /// What a run counted, by name.
    using Counts = std::vector<std::pair<std::string, double>>;
    /// The graph, run on the worker into the sink; fills the counts.
    using Run = std::function<void(Sink&, Counts&)>;

    explicit StoreIsosurface(Run run) : run_(std::move(run)) {
        worker_ = std::thread([this] {
            try {
                QueueSink sink(*this);
                Counts c;
                run_(sink, c);
                const std::lock_guard<std::mutex> lock(m_);
                counts_ = std::move(c);
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
        py::dict d;
        for (const auto& [name, value] : counts_) d[py::str(name)] = value;
        d["done"] = done_;
        return d;
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
    PayloadSet takes() const override { return Payload::points; }
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

    Run run_;
    std::thread worker_;
    mutable std::mutex m_;
    std::condition_variable cv_;
    std::deque<std::vector<PointRecord>> queue_;
    bool done_ = false, cancelled_ = false, finished_ = false;
    std::exception_ptr error_;
    Counts counts_;
};

StoreIsosurface::Counts isosplat_counts(const IsoSplatResult& r) {
    return {{"active_cells", static_cast<double>(r.sampling.active_cells)}, {"too_far", static_cast<double>(r.projection.too_far)},
            {"flat", static_cast<double>(r.projection.flat)}, {"missed", static_cast<double>(r.projection.missed)},
            {"seconds", r.seconds}};
}

/// The isosurface of a brick or sample store (chapter 3); damage to a header or to the candidate
/// buckets fails here, at the call.
std::unique_ptr<StoreIsosurface> volume_store_isosurface(const StoreObject& s, double iso, const std::string& projection,
                                                         std::uint64_t memory, int threads) {
    if (s.kind == StoreKind::point) throw py::value_error(s.path + ": a point store's isosurface takes the scattered options (field, samples, ...)");
    const double level = finite_iso(iso);
    const Projection mode = projection_of(projection);
    if (memory < (std::uint64_t{1} << 20)) throw py::value_error("memory: expected at least 1M (the brick cache's budget)");
    if (threads < 0 || threads > 1024) throw py::value_error("threads: expected 0..1024 (0: every CPU this process may use)");
    const int n = threads == 0 ? available_cpus() : threads;
    py::gil_scoped_release free;
    if (s.kind == StoreKind::sample) {
        std::shared_ptr<const SampleStore> store = SampleStore::open(s.path);
        auto source = std::make_shared<SampleStoreSource>(*store, level, SamplingParams{});  // reads the candidate buckets
        return std::make_unique<StoreIsosurface>([store, source, level, mode, n](Sink& sink, StoreIsosurface::Counts& c) {
            const IsoSplatResult r = run_isosplat_sample_store(*source, level, mode, sink, {n}, PipelineShape::two_stage);
            c = isosplat_counts(r);
            c.emplace_back("samples", static_cast<double>(source->emitted()));
        });
    }
    VolumeOpenOptions o;
    o.memory = memory;
    o.stream = true;
    o.threads = n;
    auto in = std::make_shared<VolumeInput>(open_volume_input(s.path, o));
    return std::make_unique<StoreIsosurface>([in, level, mode, n](Sink& sink, StoreIsosurface::Counts& c) {
        c = isosplat_counts(run_isosplat_input(*in, level, mode, SamplingParams{}, sink, n, PipelineShape::fused));
    });
}

/// The scattered isosurface of a point store (chapter 5), slab by slab within `memory`; the plan
/// (scans of the store) runs here, at the call, so its errors and warnings come first.
std::unique_ptr<StoreIsosurface> point_store_isosurface(const StoreObject& s, double iso, const FieldParams& field, int samples,
                                                        double reg_gap, long long max_cells, int max_level, double tolerance,
                                                        int max_iterations, double max_travel, std::uint64_t memory, int threads,
                                                        py::list& warnings) {
    const double level = finite_iso(iso);
    if (field.kind != FieldKind::mpu) throw py::value_error("field: a point store's isosurface is built slab by slab with the mpu field");
    if (!(max_travel > 0)) throw py::value_error("max_travel: a point store's slabs need a limit > 0 (cell diagonals)");
    const int n = lattice(samples);
    const FieldProjectParams np = newton_params(tolerance, max_iterations, max_travel);
    if (!(reg_gap >= 0)) throw py::value_error("reg_gap: expected a factor >= 0");
    if (max_cells < 27 || max_cells > (1LL << 31)) throw py::value_error("max_cells: expected 27..2^31");
    if (max_level < 0 || max_level > 12) throw py::value_error("max_level: expected 0..12");
    if (memory < (std::uint64_t{1} << 20)) throw py::value_error("memory: expected at least 1M");
    if (threads < 0 || threads > 1024) throw py::value_error("threads: expected 0..1024 (0: every CPU this process may use)");
    const int workers = threads == 0 ? available_cpus() : threads;
    BinningGridParams bp;
    bp.max_cells = max_cells;
    bp.max_level = max_level;
    ScatteredStoreParams sp;
    sp.memory_bytes = memory;
    sp.reg_gap = reg_gap;
    std::vector<std::string> said;
    std::shared_ptr<const ScatteredStorePlan> plan;
    {
        py::gil_scoped_release free;
        plan = std::make_shared<const ScatteredStorePlan>(plan_scattered_store(
            *s.point_store, s.path, bp, [&](const std::string& subject, const std::string& w) { said.push_back(subject + ": " + w); }));
    }
    for (const std::string& w : said) warnings.append(w);
    std::shared_ptr<const PointStore> store = s.point_store;
    py::gil_scoped_release free;
    return std::make_unique<StoreIsosurface>([store, plan, field, sp, level, n, np, workers](Sink& sink, StoreIsosurface::Counts& c) {
        ScatteredStoreReport rep;
        const ScatteredIsosurfaceStats st = run_scattered_store_isosurface(*store, *plan, field, sp, level, n, np, 0, sink, {workers}, {}, &rep);
        c = {{"stencils", static_cast<double>(st.seeds.stencils)}, {"seeds", static_cast<double>(st.seeds.seeds)},
             {"converged", static_cast<double>(st.newton.converged)}, {"slabs", static_cast<double>(rep.slabs)},
             {"retries", static_cast<double>(rep.retries)}, {"most_loaded", static_cast<double>(rep.most_loaded)},
             {"loaded", static_cast<double>(rep.loaded)}};
    });
}

/// Brick i of a point store: points (count, 3) and values (count,) float64 views of one decoded buffer.
py::dict point_brick(const StoreObject& s, std::size_t i) {
    if (s.kind != StoreKind::point) throw py::value_error(s.path + ": bricks() reads a point store's (.mlc) bricks");
    if (i >= s.point_store->bricks().size()) throw py::index_error("brick " + std::to_string(i) + " of " + std::to_string(s.point_store->bricks().size()));
    std::vector<double> xyzv;
    {
        py::gil_scoped_release free;
        s.point_store->read_brick(i, xyzv);
    }
    const auto count = static_cast<py::ssize_t>(xyzv.size() / 4);
    double* data = nullptr;
    static const double none[4] = {0, 0, 0, 0};
    const py::capsule base = owning_capsule(std::move(xyzv), &data);
    const double* d = data ? data : none;
    constexpr auto f = static_cast<py::ssize_t>(sizeof(double));
    const PointBrickEntry& e = s.point_store->bricks()[i];
    py::dict out;
    out["points"] = py::array_t<double>({count, py::ssize_t{3}}, {4 * f, f}, d, base);
    out["values"] = py::array_t<double>({count}, {4 * f}, d + 3, base);
    out["value_name"] = s.points.value_name;
    out["has_values"] = s.points.has_values;
    out["blocks"] = py::list();
    out["stats"] = py::dict(py::arg("brick") = i, py::arg("level") = e.level, py::arg("key") = e.key,
                            py::arg("first") = e.first, py::arg("bounds") = py::make_tuple(py::make_tuple(e.lo[0], e.lo[1], e.lo[2]),
                                                                                           py::make_tuple(e.hi[0], e.hi[1], e.hi[2])));
    return out;
}

const char* kind_name(StoreKind k) {
    switch (k) {
        case StoreKind::sample: return "sample";
        case StoreKind::point: return "point";
        case StoreKind::brick: break;
    }
    return "brick";
}

/// A point store's mpu field at `positions` (m, 3), slab by slab within `memory`
/// (stream/store_field_queries.hpp evaluate_store_positions, what `meshless probe STORE` writes):
/// (values (m,), gradients (m, 3)).
py::tuple point_store_probe(const StoreObject& s, const py::array& positions, const FieldParams& field, double max_gap,
                            const std::string& extrapolate, std::uint64_t memory, int threads) {
    if (s.kind != StoreKind::point) throw py::value_error(s.path + ": probe() evaluates a point store's (.mlc) field");
    if (field.kind != FieldKind::mpu) throw py::value_error("field: a point store's field is built slab by slab with the mpu field");
    if (!(max_gap >= 0) || !std::isfinite(max_gap)) throw py::value_error("max_gap: expected a factor >= 0");
    if (memory < (std::uint64_t{1} << 20)) throw py::value_error("memory: expected at least 1M");
    if (threads < 0 || threads > 1024) throw py::value_error("threads: expected 0..1024 (0: every CPU this process may use)");
    StoreQueryParams p;
    p.field = field;
    p.max_gap = max_gap;
    p.memory_bytes = memory;
    if (extrapolate == "nan") p.extrapolate = Extrapolate::nan;
    else if (extrapolate == "clamp") p.extrapolate = Extrapolate::clamp;
    else if (extrapolate == "nearest") p.extrapolate = Extrapolate::nearest;
    else throw py::value_error("extrapolate: expected nan, clamp or nearest, got '" + extrapolate + "'");
    const std::vector<Vec3> at = vec3_rows(positions, "positions");
    const auto n = static_cast<py::ssize_t>(at.size());
    py::array_t<double> values(n), grads({n, py::ssize_t{3}});
    if (at.empty()) return py::make_tuple(values, grads);
    StorePositionValues r;
    {
        py::gil_scoped_release free;
        const ScatteredStorePlan plan = open_store_queries(s.path).plan;
        StoreQueryReport rep;
        r = evaluate_store_positions(*s.point_store, plan, p, at, /*want_grad=*/true, FieldQueryRun{threads == 0 ? available_cpus() : threads, {}, {}}, rep);
    }
    std::copy(r.value.begin(), r.value.end(), values.mutable_data());
    double* g = grads.mutable_data();
    for (std::size_t i = 0; i < r.grad.size(); ++i) g[3 * i] = r.grad[i].x, g[3 * i + 1] = r.grad[i].y, g[3 * i + 2] = r.grad[i].z;
    return py::make_tuple(values, grads);
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
        .def_property_readonly("kind", [](const StoreObject& s) { return std::string(kind_name(s.kind)); })
        .def_property_readonly("count", [](const StoreObject& s) { return s.points.points; })
        .def_property_readonly("brick_count", [](const StoreObject& s) { return s.point_store ? s.point_store->bricks().size() : std::size_t{0}; })
        .def_property_readonly("bounds", [](const StoreObject& s) {
            return py::make_tuple(py::make_tuple(s.points.lo[0], s.points.lo[1], s.points.lo[2]),
                                  py::make_tuple(s.points.hi[0], s.points.hi[1], s.points.hi[2]));
        })
        .def_property_readonly("value_name", [](const StoreObject& s) { return s.points.value_name; })
        .def("_brick", &point_brick, py::arg("index"))
        .def("_probe", &point_store_probe, py::arg("positions"), py::arg("field"), py::arg("max_gap"), py::arg("extrapolate"),
             py::arg("memory"), py::arg("threads"))
        .def("_isosurface", &volume_store_isosurface, py::arg("iso"), py::arg("projection"), py::arg("memory"), py::arg("threads"))
        .def("_point_isosurface", &point_store_isosurface, py::arg("iso"), py::arg("field"), py::arg("samples"), py::arg("reg_gap"),
             py::arg("max_cells"), py::arg("max_level"), py::arg("tolerance"), py::arg("max_iterations"), py::arg("max_travel"),
             py::arg("memory"), py::arg("threads"), py::arg("warnings"));
    py::class_<StoreIsosurface>(m, "_StoreIsosurface")
        .def("_next", &StoreIsosurface::next)
        .def("_stop", &StoreIsosurface::stop)
        .def_property_readonly("stats", &StoreIsosurface::stats);
}

}  // namespace meshless::python
