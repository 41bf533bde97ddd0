// The isosurfaces of the Python module (python/README.md): chapter 3 on a NumPy volume
// (stream/isosplat_pipeline.hpp), chapter 4 on curvilinear blocks (stream/block_isosurface.hpp),
// chapter 5 on scattered points (stream/scattered_isosurface.hpp). Each runs the recipe a CLI
// command runs, into a CollectSink, with the GIL released; Ctrl-C stops it at its next batch
// (interrupt.hpp).
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "array_slices.hpp"
#include "arrays.hpp"
#include "bindings.hpp"
#include "point_arrays.hpp"
#include "field_object.hpp"
#include "interrupt.hpp"
#include "iso_params.hpp"
#include "kernels/barycentric_lattice.hpp"
#include "stream/block_isosurface.hpp"
#include "stream/field_evaluation.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"
#include "stream/projection_meta.hpp"
#include "stream/scattered_isosurface.hpp"

namespace meshless::python {

namespace {

py::dict isosurface_volume(const py::array& volume, double iso, const py::object& spacing, const py::object& origin,
                           const std::string& projection, int threads, bool shared_mapping) {
    const VolumeArray v = volume_view(volume, triple(spacing, "spacing"), triple(origin, "origin"));
    const Projection mode = projection_of(projection);
    const double level = finite_iso(iso);
    const bool slabs = shared_mapping && v.keep.is(volume);  // a file mapped shared, used in place: slab by slab
    CollectSink sink;
    IsoSplatResult r;
    run_interruptible([&](const std::atomic<bool>& stop) {
        StopSink guarded(sink, stop);
        if (slabs) {
            ArraySlices slices(v.view, /*release_pages=*/true);
            r = run_isosplat_slabs(slices, level, mode, SamplingParams{}, guarded, {threads});
        } else {
            r = run_isosplat(v.view, level, mode, SamplingParams{}, guarded, {threads});
        }
    });
    py::dict out = point_arrays(std::move(sink.points), nullptr, v.axes_swapped);
    out["stats"] = py::dict(py::arg("active_cells") = r.sampling.active_cells, py::arg("nonfinite_cells") = r.sampling.nonfinite_cells,
                            py::arg("too_far") = r.projection.too_far, py::arg("flat") = r.projection.flat,
                            py::arg("missed") = r.projection.missed, py::arg("seconds") = r.seconds);
    return out;
}

py::dict newton_stats(const FieldNewtonStats& s) {
    return py::dict(py::arg("seeds") = s.input, py::arg("converged") = s.converged, py::arg("flat") = s.flat,
                    py::arg("too_far") = s.too_far, py::arg("not_converged") = s.not_converged, py::arg("stalled") = s.stalled,
                    py::arg("nonfinite") = s.nonfinite, py::arg("evaluations") = s.evaluations);
}

py::dict isosurface_points(const py::array& points, const py::array& values, double iso, const py::object& field_arg,
                           int samples, double reg_gap, long long max_cells, int max_level, double tolerance, int max_iterations,
                           double max_travel, int threads) {
    PointSet pts = point_set_of(points, values);
    const int n = lattice(samples);
    const FieldProjectParams np = newton_params(tolerance, max_iterations, max_travel);
    if (!(reg_gap >= 0)) throw py::value_error("reg_gap: expected a factor >= 0");
    BinningGridParams bp;
    if (max_cells < 27 || max_cells > (1LL << 31)) throw py::value_error("max_cells: expected 27..2^31");
    if (max_level < 0 || max_level > 12) throw py::value_error("max_level: expected 0..12");
    bp.max_cells = max_cells;
    bp.max_level = max_level;
    // a Field object: used as it is (it must stand for these points); else the kind's parameters
    const FieldObject* given = py::isinstance<FieldObject>(field_arg) ? &field_arg.cast<const FieldObject&>() : nullptr;
    const FieldParams params = given ? FieldParams{} : field_arg.cast<FieldParams>();
    py::list warnings;
    std::vector<std::pair<std::string, std::string>> said;
    std::vector<PointRecord> records;
    ScatteredIsosurfaceStats st;
    std::unique_ptr<Field> built;
    const double level = finite_iso(iso);
    run_interruptible([&](const std::atomic<bool>& stop) {
        ScatteredIsosurfaceInput in = bin_scattered_points(std::move(pts), "points", "points", bp, reg_gap,
                                                           [&](const std::string& s, const std::string& w) { said.emplace_back(s, w); });
        const bool crossed = in.crosses(level);
        const Field* field = given ? given->field.get() : nullptr;
        if (crossed) {
            build_alongside_coverage(in, threads, [&] {
                if (!given) built = fit_field(in.points, params, threads);
            });
            if (!given) field = built.get();
        }
        if (stop) throw Stopped{};
        CollectSink sink;
        StopSink guarded(sink, stop);
        st = run_scattered_isosurface(in, crossed ? field : nullptr, iso, n, np, 0, nullptr, guarded, {threads});
        records = std::move(sink.points);
    });
    for (const auto& [s, w] : said) warnings.append(s + ": " + w);
    py::dict out = point_arrays(std::move(records));
    out["stats"] = py::dict(py::arg("stencils") = st.seeds.stencils, py::arg("crossed_stencils") = st.seeds.crossed_stencils,
                            py::arg("triangles") = st.seeds.triangles, py::arg("seeds") = st.seeds.seeds,
                            py::arg("delaunay_failures") = st.seeds.delaunay_failures, py::arg("newton") = newton_stats(st.newton));
    out["warnings"] = warnings;
    return out;
}

/// One block: (coords (ni, nj, nk, 3), values (ni, nj, nk)[, iblank (ni, nj, nk), 0 = blanked
/// [, covered (ni, nj, nk) or None, level, cell_centred]]): the last three are an AMR box's, as
/// read_multiblock reads them (kernels/structured_block.hpp).
StructuredBlock block_of(const py::handle& item, std::size_t index) {
    const auto t = item.cast<py::tuple>();
    const std::string what = "blocks[" + std::to_string(index) + "]";
    if (t.size() < 2 || t.size() == 4 || t.size() == 5 || t.size() > 6)
        throw py::value_error(what + ": expected (coords, values), (coords, values, iblank) or a Block of read_multiblock");
    auto xyz = py::array_t<double, py::array::forcecast>::ensure(t[0]);
    if (!xyz || xyz.ndim() != 4 || xyz.shape(3) != 3) throw py::value_error(what + ": coords must be an (ni, nj, nk, 3) array");
    auto val = py::array_t<double, py::array::forcecast>::ensure(t[1]);
    if (!val || val.ndim() != 3 || val.shape(0) != xyz.shape(0) || val.shape(1) != xyz.shape(1) || val.shape(2) != xyz.shape(2))
        throw py::value_error(what + ": values must be an (ni, nj, nk) array matching coords");
    StructuredBlock b;
    b.name = what;
    b.dims = {xyz.shape(0), xyz.shape(1), xyz.shape(2)};
    for (int a = 0; a < 3; ++a)
        if (b.dims[static_cast<std::size_t>(a)] < 2) throw py::value_error(what + ": every axis needs at least 2 nodes");
    const auto c = xyz.unchecked<4>();
    const auto v = val.unchecked<3>();
    const std::size_t count = static_cast<std::size_t>(b.node_count());
    b.node.resize(count);
    b.value.resize(count);
    std::vector<std::uint8_t> valid(count, 1);
    bool any_invalid = false;
    std::optional<py::array_t<long long, py::array::forcecast>> ib;
    if (t.size() == 3 && !t[2].is_none()) {
        ib = py::array_t<long long, py::array::forcecast>::ensure(t[2]);
        if (!*ib || ib->ndim() != 3 || ib->shape(0) != val.shape(0) || ib->shape(1) != val.shape(1) || ib->shape(2) != val.shape(2))
            throw py::value_error(what + ": iblank must be an (ni, nj, nk) array matching values");
    }
    for (py::ssize_t k = 0; k < val.shape(2); ++k)
        for (py::ssize_t j = 0; j < val.shape(1); ++j)
            for (py::ssize_t i = 0; i < val.shape(0); ++i) {
                const auto n = static_cast<std::size_t>(b.index(i, j, k));
                b.node[n] = Vec3{c(i, j, k, 0), c(i, j, k, 1), c(i, j, k, 2)};
                b.value[n] = v(i, j, k);
                const bool ok = std::isfinite(b.value[n]) && std::isfinite(b.node[n].x) && std::isfinite(b.node[n].y) &&
                                std::isfinite(b.node[n].z) && (!ib || ib->at(i, j, k) != 0);
                if (!ok) valid[n] = 0, any_invalid = true;
            }
    if (any_invalid) b.valid = std::move(valid);
    if (t.size() == 6) {  // an AMR box: the nodes a finer level covers, its level, cell centres
        if (!t[3].is_none()) {
            const auto cov = py::array_t<std::uint8_t, py::array::forcecast>::ensure(t[3]);
            if (!cov || cov.ndim() != 3 || cov.shape(0) != val.shape(0) || cov.shape(1) != val.shape(1) || cov.shape(2) != val.shape(2))
                throw py::value_error(what + ": covered must be an (ni, nj, nk) array matching values");
            const auto c3 = cov.unchecked<3>();
            b.covered.assign(count, 0);
            for (py::ssize_t k = 0; k < val.shape(2); ++k)
                for (py::ssize_t j = 0; j < val.shape(1); ++j)
                    for (py::ssize_t i = 0; i < val.shape(0); ++i) b.covered[static_cast<std::size_t>(b.index(i, j, k))] = c3(i, j, k) ? 1 : 0;
        }
        b.level = t[4].cast<int>();
        if (b.level < 0) throw py::value_error(what + ": level must be >= 0");
        b.cell_centred = t[5].cast<bool>();
    }
    return b;
}

py::dict isosurface_blocks(const py::list& blocks, double iso, const FieldParams& params, int samples, double tolerance,
                           int max_iterations, double max_travel, int threads) {
    if (blocks.empty()) throw py::value_error("blocks: expected at least one (coords, values) block");
    Multiblock mb;
    mb.format = "arrays";
    for (std::size_t i = 0; i < blocks.size(); ++i) mb.blocks.push_back(block_of(blocks[i], i));
    const int n = lattice(samples);
    const FieldProjectParams np = newton_params(tolerance, max_iterations, max_travel);
    std::vector<PointRecord> records;
    std::vector<std::uint32_t> ids;
    BlockIsosurfaceStats st;
    const double level = finite_iso(iso);
    run_interruptible([&](const std::atomic<bool>& stop) {
        const BlockIsosurfaceInput in = plan_block_isosurface(std::move(mb), "blocks", level);
        std::unique_ptr<Field> field;
        if (in.plan.active_cells > 0) field = fit_field(to_point_set(in.mb), params, threads);
        if (stop) throw Stopped{};
        CollectSink sink;
        StopSink guarded(sink, stop);
        st = run_block_isosurface(in, field.get(), iso, n, np, nullptr, guarded, {threads});
        records = std::move(sink.points);
        ids = std::move(sink.blocks);
    });
    if (ids.size() != records.size()) ids.assign(records.size(), 0);
    py::dict out = point_arrays(std::move(records), &ids);
    out["stats"] = py::dict(py::arg("cells") = st.seeds.cells, py::arg("active_cells") = st.seeds.active_cells,
                            py::arg("invalid_cells") = st.seeds.invalid_cells, py::arg("triangles") = st.seeds.triangles,
                            py::arg("seeds") = st.seeds.seeds, py::arg("newton") = newton_stats(st.newton));
    return out;
}

}  // namespace

void bind_isosurface(py::module_& m) {
    m.def("_isosurface_volume", &isosurface_volume, py::arg("volume"), py::arg("iso"), py::arg("spacing"), py::arg("origin"),
          py::arg("projection"), py::arg("threads"), py::arg("shared_mapping"));
    m.def("_isosurface_points", &isosurface_points, py::arg("points"), py::arg("values"), py::arg("iso"), py::arg("field"),
          py::arg("samples"), py::arg("reg_gap"), py::arg("max_cells"), py::arg("max_level"), py::arg("tolerance"),
          py::arg("max_iterations"), py::arg("max_travel"), py::arg("threads"));
    m.def("_isosurface_blocks", &isosurface_blocks, py::arg("blocks"), py::arg("iso"), py::arg("params"), py::arg("samples"),
          py::arg("tolerance"), py::arg("max_iterations"), py::arg("max_travel"), py::arg("threads"));
}

}  // namespace meshless::python
