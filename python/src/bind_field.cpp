// meshless.Field (python/README.md): fit, evaluate (values and gradients, the GIL released,
// stream/field_evaluation.hpp), save/load of the .mlf `meshless fit` writes; and the field
// parameters the isosurfaces of points and blocks take (kernels/field_params.hpp).
#include <pybind11/stl.h>

#include <cmath>

#include "bindings.hpp"
#include "field_object.hpp"
#include "kernels/make_field.hpp"
#include "kernels/point_set_identity.hpp"
#include "stream/field_evaluation.hpp"

namespace meshless::python {

PointSet point_set_of(const py::array& points, const py::array& values) {
    const std::vector<Vec3> pos = vec3_rows(points, "points");
    const std::vector<double> val = real_values(values, pos.size(), "values");
    PointSet s;
    s.pos.reserve(pos.size());
    s.value.reserve(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const Vec3& p = pos[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(val[i])) {
            ++s.dropped_nonfinite;
            continue;
        }
        s.pos.push_back(p);
        s.value.push_back(val[i]);
    }
    s.blocks.push_back(PointSetBlock{"points", {static_cast<std::int64_t>(s.pos.size()), 1, 1}, 0, s.pos.size()});
    return s;
}

namespace {

FieldParams field_params(const std::string& kind, double hardy_c, double hardy_c_world, double binning, int max_points,
                         double alpha, int local_points, bool normalise_axes) {
    FieldParams p;
    if (!parse_field_kind(kind, p.kind)) throw py::value_error("kind: expected 'mpu', 'rbf-grid' or 'global-rbf', got '" + kind + "'");
    if (!(hardy_c > 0) || !std::isfinite(hardy_c)) throw py::value_error("hardy_c: expected a number > 0 (a fraction of the bounding-box diagonal)");
    p.hardy_c_rel = hardy_c;
    if (!(hardy_c_world >= 0) || !std::isfinite(hardy_c_world)) throw py::value_error("hardy_c_world: expected a number >= 0 (0: use hardy_c)");
    p.hardy_c_world = hardy_c_world;
    if (!(binning > 0) || !std::isfinite(binning)) throw py::value_error("binning: expected a number > 0");
    p.binning_m = binning;
    if (max_points < 8 || max_points > 100000) throw py::value_error("max_points: expected 8..100000");
    p.mpu_max_points = static_cast<std::uint32_t>(max_points);
    p.mpu_min_points = std::min(p.mpu_min_points, p.mpu_max_points);
    if (!(alpha > 0.5) || alpha > kMaxMpuAlpha) throw py::value_error("alpha: expected a factor in (0.5, 4]");
    p.mpu_alpha = alpha;
    if (local_points < 0 || local_points > 100000) throw py::value_error("local_points: expected 0..100000");
    p.rbf_grid_local_points = static_cast<std::uint32_t>(local_points);
    p.normalise_axes = normalise_axes;
    return p;
}

std::unique_ptr<FieldObject> fit(const py::array& points, const py::array& values, const FieldParams& params, int threads,
                                 const std::string& value_name) {
    PointSet s = point_set_of(points, values);
    auto f = std::make_unique<FieldObject>();
    f->params = params;
    {
        py::gil_scoped_release free;
        f->field = fit_field(s, params, threads, &f->stats);
        f->data.identity = point_set_identity(s);
    }
    f->data.dropped_nonfinite = s.dropped_nonfinite;
    f->data.value_name = value_name.substr(0, 1024);
    return f;
}

py::array evaluate(const FieldObject& f, const py::array& queries, bool gradient, int threads) {
    const std::vector<Vec3> at = vec3_rows(queries, "queries");
    const auto n = static_cast<py::ssize_t>(at.size());
    if (!gradient) {
        py::array_t<double> out(n);
        {
            py::gil_scoped_release free;
            evaluate_field(*f.field, at, std::span<double>(out.mutable_data(), at.size()), {}, {threads});
        }
        return out;
    }
    std::vector<double> value(at.size());
    py::array_t<double> out({n, py::ssize_t{3}});
    {
        py::gil_scoped_release free;
        std::vector<Vec3> grad(at.size());
        evaluate_field(*f.field, at, value, grad, {threads});
        double* o = out.mutable_data();
        for (std::size_t i = 0; i < grad.size(); ++i) o[3 * i] = grad[i].x, o[3 * i + 1] = grad[i].y, o[3 * i + 2] = grad[i].z;
    }
    return out;
}

std::unique_ptr<FieldObject> load(const std::string& path) {
    FieldFile ff;
    {
        py::gil_scoped_release free;
        ff = read_field_file(path);
    }
    auto f = std::make_unique<FieldObject>();
    f->field = std::move(ff.field);
    f->params = ff.info.params;
    f->data = ff.info.data;
    f->stats = ff.info.stats;
    return f;
}

py::dict stats_of(const FieldBuildStats& s) {
    return py::dict(py::arg("input_points") = s.input_points, py::arg("merged_points") = s.merged_points,
                    py::arg("locals") = s.locals, py::arg("interpolated") = s.interpolated,
                    py::arg("regularised") = s.regularised, py::arg("linear_fallback") = s.linear_fallback,
                    py::arg("hardy_c_world") = s.hardy_c_world, py::arg("memory_bytes") = s.memory_bytes,
                    py::arg("build_seconds") = s.build_seconds);
}

}  // namespace

void bind_field(py::module_& m) {
    py::class_<FieldParams>(m, "_FieldParams");
    m.def("_field_params", &field_params, py::arg("kind"), py::arg("hardy_c"), py::arg("hardy_c_world"), py::arg("binning"),
          py::arg("max_points"), py::arg("alpha"), py::arg("local_points"), py::arg("normalise_axes"));
    py::class_<FieldObject>(m, "_Field")
        .def(py::init(&fit), py::arg("points"), py::arg("values"), py::arg("params"), py::arg("threads"), py::arg("value_name"))
        .def("_evaluate", &evaluate, py::arg("queries"), py::arg("gradient"), py::arg("threads"))
        .def("_save", [](const FieldObject& f, const std::string& path, int zstd_level) {
                if (zstd_level < 0 || zstd_level > 19) throw py::value_error("zstd_level: expected 0..19");
                py::gil_scoped_release free;
                write_field_file(path, *f.field, f.params, f.data, f.stats, zstd_level);
            }, py::arg("path"), py::arg("zstd_level"))
        .def_static("_load", &load, py::arg("path"))
        .def_property_readonly("kind", [](const FieldObject& f) { return f.field->name(); })
        .def_property_readonly("bounds", [](const FieldObject& f) {
            const auto b = f.field->bounds();
            return py::make_tuple(py::make_tuple(b[0].x, b[0].y, b[0].z), py::make_tuple(b[1].x, b[1].y, b[1].z));
        })
        .def_property_readonly("points", [](const FieldObject& f) { return f.data.identity.count; })
        .def_property_readonly("value_name", [](const FieldObject& f) { return f.data.value_name; })
        .def_property_readonly("stats", [](const FieldObject& f) { return stats_of(f.stats); });
}

}  // namespace meshless::python
