// Levels of detail in the Python module (python/README.md): meshless.hierarchy builds the cluster
// binary tree of dissertation chapter 6 (sections 6.1, 6.3) over NumPy points and values through
// stream/cluster_hierarchy.hpp, what `meshless hierarchy` runs; ClusterTree.lod extracts a level of
// detail (section 6.4, level- or error-based) as scattered points and values (section 6.5), what
// `meshless lod` runs; save/load read and write the .mlh (formats/cluster_tree_file.hpp, the same
// bytes as the command's for the same samples, options and value name). The LOD's arrays own the
// extraction's buffers: points (n, 3) float64 (world units) and values (n,) float64, nothing copied.
// The GIL is released while a tree is built, extracted, read or written.
// Errors: ValueError for options out of their domain, DataError for data that makes no tree and for
// a damaged .mlh, OSError for files that cannot be read or written.
#include <pybind11/stl.h>

#include <cmath>
#include <limits>

#include "arrays.hpp"
#include "bindings.hpp"
#include "field_object.hpp"
#include "formats/cluster_tree_file.hpp"
#include "formats/field_hint.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/errors.hpp"
#include "kernels/field_params.hpp"
#include "stream/available_cpus.hpp"
#include "stream/cluster_hierarchy.hpp"

namespace meshless::python {

namespace {

struct TreeObject {
    ClusterTree tree;
    std::vector<std::string> notes;  ///< the build's warnings and notes
};

CbtParams hierarchy_params(const py::object& max_splits, double max_error, long long min_cluster, long long neighbours,
                           double hardy_c, const py::object& hardy_c_world, const std::string& pca_scaling,
                           const std::string& split_order, double size_term, const std::string& cluster_value) {
    CbtParams p;
    if (!max_splits.is_none()) {
        const long long n = max_splits.cast<long long>();
        if (n < 0) throw py::value_error("max_splits: expected a count >= 0");
        p.max_splits = static_cast<std::uint64_t>(n);
    }
    if (!(max_error >= 0) || !std::isfinite(max_error)) throw py::value_error("max_error: expected a number >= 0");
    p.max_error = max_error;
    if (min_cluster < 2 || min_cluster > 1000000000) throw py::value_error("min_cluster: expected 2..10^9");
    p.min_cluster = static_cast<std::uint32_t>(min_cluster);
    if (neighbours < 1 || neighbours > 1000) throw py::value_error("neighbours: expected 1..1000");
    p.neighbours = static_cast<std::uint32_t>(neighbours);
    if (!(hardy_c >= 0) || !std::isfinite(hardy_c)) throw py::value_error("hardy_c: expected a number >= 0");
    p.hardy_c_rel = hardy_c;
    if (!hardy_c_world.is_none()) {
        p.hardy_c_world = hardy_c_world.cast<double>();
        if (!(p.hardy_c_world > 0) || !std::isfinite(p.hardy_c_world)) throw py::value_error("hardy_c_world: expected a number > 0");
    }
    if (pca_scaling == "raw") p.scaling = PcaScaling::raw;
    else if (pca_scaling == "normalised" || pca_scaling == "normalized") p.scaling = PcaScaling::normalised;
    else throw py::value_error("pca_scaling: expected 'normalised' or 'raw', got '" + pca_scaling + "'");
    if (split_order == "weighted") p.order = CbtSplitOrder::weighted;
    else if (split_order == "max-error" || split_order == "max_error") p.order = CbtSplitOrder::max_error;
    else throw py::value_error("split_order: expected 'weighted' or 'max-error', got '" + split_order + "'");
    if (!(size_term >= 0 && size_term <= 100)) throw py::value_error("size_term: expected a number in [0, 100]");
    p.size_term = size_term;
    if (cluster_value == "mean") p.value = CbtValueKind::mean;
    else if (cluster_value == "fit") p.value = CbtValueKind::fit;
    else throw py::value_error("cluster_value: expected 'mean' or 'fit', got '" + cluster_value + "'");
    return p;
}

std::unique_ptr<TreeObject> hierarchy(const py::array& points, const py::array& values, const CbtParams& p, int threads,
                                      const std::string& value_name) {
    if (threads < 0 || threads > 1024) throw py::value_error("threads: expected 0..1024 (0: every CPU this process may use)");
    PointSet s = point_set_of(points, values);
    s.value_name = value_name;
    auto t = std::make_unique<TreeObject>();
    py::gil_scoped_release free;
    t->tree = build_cluster_hierarchy(s, p, threads == 0 ? available_cpus() : threads, "points");
    t->notes = cluster_hierarchy_notes(t->tree, p);
    return t;
}

py::dict lod(const TreeObject& t, const py::object& level, const py::object& error, const py::object& count,
             const py::object& fraction) {
    if (int(!level.is_none()) + int(!error.is_none()) + int(!count.is_none()) + int(!fraction.is_none()) != 1)
        throw py::value_error("lod: give one of count=, fraction=, level= or error=");
    PointSetOptions o;
    if (!count.is_none()) {
        const long long n = count.cast<long long>();
        if (n < 1) throw py::value_error("count: expected a count >= 1");
        o.lod_count = static_cast<std::uint64_t>(n);
    } else if (!fraction.is_none()) {
        const double f = fraction.cast<double>();
        if (!(f > 0 && f <= 1)) throw py::value_error("fraction: expected a number in (0, 1]");
        o.lod_fraction = f;
    } else if (!level.is_none()) {
        const long long L = level.cast<long long>();
        if (L < 0 || L > 0xFFFFFFFFll) throw py::value_error("level: expected a depth >= 0");
        o.lod_level = static_cast<std::uint32_t>(L);
    } else {
        const double e = error.cast<double>();
        if (!(e >= 0) || !std::isfinite(e)) throw py::value_error("error: expected a number >= 0");
        o.lod_error = e;
    }
    std::vector<std::string> warnings;
    LodExtraction e;
    ClusterTreeLodRequest r;
    {
        py::gil_scoped_release free;
        r = cluster_tree_lod_request(t.tree, o);
        if (r.clamped) warnings.push_back("warning: " + r.note);
        e = extract_lod(t.tree, r);
        if (const std::string w = lod_overshoot_warning(t.tree, e); !w.empty()) warnings.push_back(w);
    }
    const auto n = static_cast<py::ssize_t>(e.points.size());
    Vec3* pos = nullptr;
    double* val = nullptr;
    static_assert(sizeof(Vec3) == 3 * sizeof(double));
    static const Vec3 no_point{};
    static const double no_value = 0;
    const py::capsule pb = owning_capsule(std::move(e.points.pos), &pos);
    const py::capsule vb = owning_capsule(std::move(e.points.value), &val);
    py::dict out;
    out["points"] = view_of<double>(pb, pos ? &pos->x : &no_point.x, {n, 3}, {sizeof(Vec3), sizeof(double)});
    out["values"] = view_of<double>(vb, val ? val : &no_value, {n}, {sizeof(double)});
    // the Hardy c its points reconstruct best with travels with them, as `meshless lod` writes it (formats/field_hint.hpp)
    out["comments"] = std::vector<std::string>{"meshless lod " + r.description, field_hint_line(lod_hardy_c_rel(t.tree.params.order == CbtSplitOrder::max_error))};
    out["warnings"] = warnings;
    out["stats"] = py::dict(py::arg("lod") = r.description, py::arg("points") = n, py::arg("seconds") = e.seconds,
                            py::arg("outside_range") = e.outside);
    return out;
}

py::dict tree_stats(const TreeObject& t) {
    const CbtStats& s = t.tree.stats;
    return py::dict(py::arg("samples") = s.samples, py::arg("dropped_nonfinite") = s.dropped_nonfinite, py::arg("nodes") = t.tree.nodes.size(),
                    py::arg("splits") = s.splits, py::arg("skipped") = s.skipped, py::arg("depth") = s.depth,
                    py::arg("error_reached") = s.error_reached, py::arg("hardy_c_world") = s.hardy_c_world, py::arg("seconds") = s.seconds);
}

}  // namespace

void bind_hierarchy(py::module_& m) {
    py::class_<CbtParams>(m, "_HierarchyParams");
    m.def("_hierarchy_params", &hierarchy_params, py::arg("max_splits"), py::arg("max_error"), py::arg("min_cluster"),
          py::arg("neighbours"), py::arg("hardy_c"), py::arg("hardy_c_world"), py::arg("pca_scaling"), py::arg("split_order"),
          py::arg("size_term"), py::arg("cluster_value"));
    m.def("_hierarchy", &hierarchy, py::arg("points"), py::arg("values"), py::arg("params"), py::arg("threads"), py::arg("value_name"));
    py::class_<TreeObject>(m, "_ClusterTree")
        .def("_lod", &lod, py::arg("level"), py::arg("error"), py::arg("count"), py::arg("fraction"))
        .def("_save", [](const TreeObject& t, const std::string& path) {
            py::gil_scoped_release free;
            write_cluster_tree_file(path, t.tree);
        })
        .def_static("_load", [](const std::string& path) {
            auto t = std::make_unique<TreeObject>();
            py::gil_scoped_release free;
            t->tree = read_cluster_tree_file(path);
            return t;
        })
        .def_readonly("notes", &TreeObject::notes)
        .def_property_readonly("stats", &tree_stats)
        .def_property_readonly("depth", [](const TreeObject& t) { return t.tree.stats.depth; })
        .def_property_readonly("value_name", [](const TreeObject& t) { return t.tree.value_name; })
        .def_property_readonly("value_range", [](const TreeObject& t) { return py::make_tuple(t.tree.value_range[0], t.tree.value_range[1]); })
        .def_property_readonly("bounds", [](const TreeObject& t) {
            const auto& b = t.tree.bounds;
            return py::make_tuple(py::make_tuple(b[0].x, b[0].y, b[0].z), py::make_tuple(b[1].x, b[1].y, b[1].z));
        });
}

}  // namespace meshless::python
