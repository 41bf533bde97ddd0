// meshless.mc (python/README.md): the marching-cubes mesh of a NumPy volume (the section-3.6
// baseline, the graph `meshless mc` runs: McSlabSource -> MarchingCubesStage -> MeshWeldSink),
// as (vertices (n, 3) float32, faces (m, 3) uint32, normals (n, 3) float32) sharing capsule-owned
// buffers. Normals point toward decreasing values and faces wind counter-clockwise seen from the
// normal side, as in VTK; a C-ordered volume (seen with x and z swapped) gets both swapped back.
#include <cmath>

#include "arrays.hpp"
#include "bindings.hpp"
#include "stream/marching_cubes_stage.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/runner.hpp"

namespace meshless::python {

namespace {

py::tuple mc(const py::array& volume, double iso, const py::object& spacing, const py::object& origin, int threads) {
    if (!std::isfinite(iso)) throw py::value_error("iso: expected a finite number");
    const VolumeArray v = volume_view(volume, triple(spacing, "spacing"), triple(origin, "origin"));
    Mesh mesh;
    {
        py::gil_scoped_release free;
        McSlabSource source(v.view.grid);
        const MarchingCubesStage stage(v.view, iso);
        MeshWeldSink sink;
        const Stage* stages[] = {&stage};
        run_pipeline(source, stages, sink, {threads});
        mesh = sink.mesh();
    }
    if (v.axes_swapped) {  // a reflection: swap x and z back and turn every triangle over
        for (std::size_t i = 0; i + 2 < mesh.xyz.size(); i += 3) std::swap(mesh.xyz[i], mesh.xyz[i + 2]);
        for (std::size_t i = 0; i + 2 < mesh.normals.size(); i += 3) std::swap(mesh.normals[i], mesh.normals[i + 2]);
        for (std::size_t t = 0; t + 2 < mesh.tri.size(); t += 3) std::swap(mesh.tri[t + 1], mesh.tri[t + 2]);
    }
    const auto nv = static_cast<py::ssize_t>(mesh.vertex_count()), nt = static_cast<py::ssize_t>(mesh.triangle_count());
    const bool has_normals = !mesh.normals.empty();
    float *xyz = nullptr, *nrm = nullptr;
    std::uint32_t* tri = nullptr;
    const py::capsule a = owning_capsule(std::move(mesh.xyz), &xyz), b = owning_capsule(std::move(mesh.tri), &tri),
                      c = owning_capsule(std::move(mesh.normals), &nrm);
    static const float nof = 0;
    static const std::uint32_t noi = 0;
    constexpr py::ssize_t f = sizeof(float), u = sizeof(std::uint32_t);
    return py::make_tuple(view_of<float>(a, xyz ? xyz : &nof, {nv, 3}, {3 * f, f}),
                          view_of<std::uint32_t>(b, tri ? tri : &noi, {nt, 3}, {3 * u, u}),
                          view_of<float>(c, nrm ? nrm : &nof, {has_normals ? nv : 0, 3}, {3 * f, f}));
}

}  // namespace

void bind_mesh(py::module_& m) {
    m.def("_mc", &mc, py::arg("volume"), py::arg("iso"), py::arg("spacing"), py::arg("origin"), py::arg("threads"));
}

}  // namespace meshless::python
