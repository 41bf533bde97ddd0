// Files read into NumPy arrays in the Python module (python/README.md), through the readers the
// commands use, nothing parsed here:
// - read_volume: any volume `meshless isosurface` reads (stream/volume_input.hpp load_volume, the
//   one place a volume input is opened: raw, NRRD, MetaImage, VTK, VTI, vtk.js, SLC, NIfTI, Voreen,
//   DICOM, a brick store read whole), its samples mapped from the file where they lie raw in it
//   (formats/volume_reader.hpp map_volume) and handed to NumPy as an [x, y, z] Fortran-ordered
//   array whose capsule owns the Volume: no copy; the patient's axes from the header
//   (formats/anatomical_frame.hpp).
// - read_point_set: any point set `meshless fit` reads (formats/point_set_reader.hpp: CSV, PLY,
//   VTP, VTS, NumPy .npy, PLOT3D, .mlc point stores, .mlh levels of detail, volumes as points),
//   positions (n, 3) and values (n,) float64 views of the reader's vectors; the oriented PLY of
//   `meshless isosurface` (x y z nx ny nz radius value: formats/ply_points.hpp) as oriented points.
// - read_multiblock: curvilinear blocks and AMR boxes (formats/multiblock_reader.hpp) as
//   (ni, nj, nk, 3) coordinate and (ni, nj, nk) value views of each block's lattice, i fastest.
// Units: the files'. Errors: the readers' (FormatError -> meshless.DataError, IoError -> OSError,
// InvalidArgument -> ValueError), one line naming the file. The GIL is released while reading.
#include <pybind11/stl.h>

#include <memory>
#include <optional>

#include "arrays.hpp"
#include "bindings.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/ply.hpp"
#include "formats/ply_points.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_store.hpp"
#include "point_arrays.hpp"
#include "stream/volume_input.hpp"

namespace meshless::python {

namespace {

py::dtype dtype_of(SampleType t) {
    switch (t) {
        case SampleType::u8: return py::dtype::of<std::uint8_t>();
        case SampleType::i16: return py::dtype::of<std::int16_t>();
        case SampleType::u16: return py::dtype::of<std::uint16_t>();
        case SampleType::f32: break;
    }
    return py::dtype::of<float>();
}

py::tuple tuple3(const std::array<double, 3>& a) { return py::make_tuple(a[0], a[1], a[2]); }

/// A Volume's samples as an [x, y, z] array (x fastest: Fortran order) owned by a capsule holding it.
py::array volume_array(Volume&& v) {
    auto* held = new Volume(std::move(v));
    const py::capsule base(held, [](void* p) { delete static_cast<Volume*>(p); });
    const auto s = static_cast<py::ssize_t>(sample_size(held->type));
    const auto& d = held->grid.dims;
    static const std::uint64_t none = 0;
    const void* data = held->bytes.size() ? static_cast<const void*>(held->bytes.data()) : &none;
    return py::array(dtype_of(held->type), {d[0], d[1], d[2]}, {s, s * d[0], s * d[0] * d[1]}, data, base);
}

py::dict read_volume(const std::string& path, const std::optional<std::array<std::int64_t, 3>>& dims,
                     const std::optional<std::string>& dtype, bool big_endian,
                     const std::optional<std::array<double, 3>>& spacing, const std::string& series,
                     const std::string& array, const std::optional<std::uint64_t>& memory, int resolution_level) {
    if (path == "-") throw py::value_error("read_volume: give a file's path (standard input is the CLI's)");
    VolumeOpenOptions o;
    o.raw.dims = dims;
    if (dtype) {
        o.raw.type = parse_sample_type(*dtype);
        if (!o.raw.type) throw py::value_error("dtype: expected uint8, int16, uint16 or float32, got '" + *dtype + "'");
    }
    if (dims)
        for (const std::int64_t n : *dims)
            if (n < 1) throw py::value_error("dims: expected three positive integers");
    if (spacing)
        for (const double s : *spacing)
            if (!(s > 0) || s > 3.4e38) throw py::value_error("spacing: expected three numbers > 0 (at most 3.4e38)");
    o.raw.big_endian = big_endian;
    o.raw.spacing = spacing;
    o.raw.series = series;
    o.raw.array = array;
    if (resolution_level < 0) throw py::value_error("resolution_level: expected a level >= 0");
    o.raw.resolution_level = resolution_level;
    o.raw_given = dims || dtype || big_endian || spacing;
    o.memory = memory;
    std::vector<std::string> warnings;
    o.warn = [&](const std::string& w) { warnings.push_back(w); };
    Volume v;
    std::optional<AnatomicalFrame> frame;
    std::string format = "brick-store", length_unit, value_unit;
    {
        py::gil_scoped_release free;
        if (is_brick_store(path)) {
            VolumeOpenOptions header = o;
            header.memory = std::uint64_t{16} << 20;  // the header and index only
            const VolumeInput in = open_volume_input(path, header);
            frame = in.frame;
            length_unit = in.length_unit;
            value_unit = in.value_unit;
        } else {
            const VolumeInfo vi = probe_volume(path, o.raw);
            frame = vi.frame;
            format = vi.format;
            length_unit = vi.length_unit;
            value_unit = vi.value_unit;
        }
        v = load_volume(path, o, /*map=*/true);
    }
    py::dict out;
    out["format"] = format;
    out["spacing"] = tuple3(v.grid.spacing);
    out["origin"] = tuple3(v.grid.origin);
    if (frame) {
        py::array_t<double> axes({3, 3});
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) axes.mutable_at(i, j) = frame->axis[static_cast<std::size_t>(i)][j];
        out["patient_axes"] = axes;
        out["patient_axes_source"] = frame->source;
    } else {
        out["patient_axes"] = py::none();
        out["patient_axes_source"] = py::none();
    }
    out["length_unit"] = length_unit.empty() ? py::object(py::none()) : py::object(py::str(length_unit));
    out["value_unit"] = value_unit.empty() ? py::object(py::none()) : py::object(py::str(value_unit));
    out["warnings"] = warnings;
    out["array"] = volume_array(std::move(v));
    return out;
}

/// positions (n, 3) and values (n,) float64 views of a PointSet's vectors, owned by one capsule.
py::dict scattered_arrays(PointSet&& ps) {
    auto* held = new PointSet(std::move(ps));
    const py::capsule base(held, [](void* p) { delete static_cast<PointSet*>(p); });
    const auto n = static_cast<py::ssize_t>(held->pos.size());
    static const Vec3 no_point{};
    static const double no_value = 0;
    const double* p = n ? &held->pos[0].x : &no_point.x;
    const double* val = n ? held->value.data() : &no_value;
    constexpr auto d = static_cast<py::ssize_t>(sizeof(double));
    py::dict out;
    out["points"] = py::array_t<double>({n, py::ssize_t{3}}, {3 * d, d}, p, base);
    out["values"] = py::array_t<double>({n}, {d}, val, base);
    py::list blocks;
    for (const PointSetBlock& b : held->blocks)
        blocks.append(py::dict(py::arg("name") = b.name, py::arg("dims") = py::make_tuple(b.dims[0], b.dims[1], b.dims[2]),
                               py::arg("first") = b.first, py::arg("count") = b.count));
    out["blocks"] = blocks;
    out["value_name"] = held->value_name;
    out["has_values"] = held->has_values;
    out["stats"] = py::dict(py::arg("points") = held->pos.size(), py::arg("dropped_nonfinite") = held->dropped_nonfinite,
                            py::arg("dropped_blanked") = held->dropped_blanked);
    return out;
}

PointSetOptions point_set_options(const std::string& value, const std::string& columns, int q_component,
                                  const std::optional<std::uint32_t>& level, const std::optional<double>& error) {
    PointSetOptions o;
    o.value_name = value;
    o.columns = columns;
    if (q_component < 0 || q_component > 5) throw py::value_error("q_component: expected 0..5 (rho, rho*u, rho*v, rho*w, rho*E, |velocity|)");
    o.q_component = q_component;
    o.lod_level = level;
    o.lod_error = error;
    return o;
}

/// The vertices of a PLY carry the oriented points' properties (nx and radius besides x y z).
bool oriented_ply(const std::string& path) {
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    for (char& c : ext) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    if (ext != ".ply") return false;
    const PlyReader r(path);
    const int v = r.header().find("vertex");
    if (v < 0) return false;
    const PlyElement& e = r.header().elements[static_cast<std::size_t>(v)];
    return e.find("nx") >= 0 && e.find("radius") >= 0;
}

py::dict read_point_set_arrays(const std::string& path, const std::string& value, const std::string& columns, int q_component,
                               const std::optional<std::uint32_t>& level, const std::optional<double>& error) {
    if (path == "-") throw py::value_error("read_points: give a file's path (standard input is the CLI's)");
    const PointSetOptions o = point_set_options(value, columns, q_component, level, error);
    std::optional<PlyPoints> oriented;
    PointSet ps;
    {
        py::gil_scoped_release free;
        if (value.empty() && columns.empty() && oriented_ply(path)) oriented = read_ply_points(path);
        else ps = read_point_set(path, o);
    }
    if (oriented) {
        const bool blocks = !oriented->block.empty();
        py::dict out = point_arrays(std::move(oriented->points), blocks ? &oriented->block : nullptr);
        out["comments"] = oriented->comments;
        return out;
    }
    return scattered_arrays(std::move(ps));
}

/// A block's lattice as views: coords (ni, nj, nk, 3), values (ni, nj, nk) float64, valid and
/// covered (ni, nj, nk) uint8 or None; all owned by one capsule holding the block.
py::dict block_arrays(StructuredBlock&& blk) {
    auto* held = new StructuredBlock(std::move(blk));
    const py::capsule base(held, [](void* p) { delete static_cast<StructuredBlock*>(p); });
    const auto& d = held->dims;
    constexpr auto f = static_cast<py::ssize_t>(sizeof(double));
    const py::ssize_t v = 3 * f;
    py::dict out;
    out["name"] = held->name;
    out["coords"] = py::array_t<double>({d[0], d[1], d[2], py::ssize_t{3}}, {v, v * d[0], v * d[0] * d[1], f}, &held->node[0].x, base);
    out["values"] = py::array_t<double>({d[0], d[1], d[2]}, {f, f * d[0], f * d[0] * d[1]}, held->value.data(), base);
    const auto mask = [&](const std::vector<std::uint8_t>& m) -> py::object {
        if (m.empty()) return py::none();
        return py::array_t<std::uint8_t>({d[0], d[1], d[2]}, {py::ssize_t{1}, d[0], d[0] * d[1]}, m.data(), base);
    };
    out["valid"] = mask(held->valid);
    out["covered"] = mask(held->covered);
    out["level"] = held->level;
    out["cell_centred"] = held->cell_centred;
    return out;
}

py::dict read_blocks(const std::vector<std::string>& paths, const std::string& value, int q_component) {
    if (paths.empty()) throw py::value_error("read_multiblock: give at least one file");
    const PointSetOptions o = point_set_options(value, "", q_component, std::nullopt, std::nullopt);
    Multiblock mb;
    {
        py::gil_scoped_release free;
        mb = read_multiblock(paths, o);
    }
    py::list blocks;
    for (StructuredBlock& b : mb.blocks) {
        if (b.node_count() < 1 || b.node.size() != static_cast<std::size_t>(b.node_count()))
            throw FormatError(paths[0] + ": block '" + b.name + "' holds no lattice");
        blocks.append(block_arrays(std::move(b)));
    }
    py::dict out;
    out["blocks"] = blocks;
    out["value_name"] = mb.value_name;
    out["format"] = mb.format;
    out["notes"] = mb.notes;
    out["stats"] = py::dict(py::arg("blanked") = mb.blanked, py::arg("nonfinite") = mb.nonfinite, py::arg("covered") = mb.covered);
    return out;
}

}  // namespace

void bind_read(py::module_& m) {
    m.def("_read_volume", &read_volume, py::arg("path"), py::arg("dims"), py::arg("dtype"), py::arg("big_endian"),
          py::arg("spacing"), py::arg("series"), py::arg("array"), py::arg("memory"), py::arg("resolution_level"));
    m.def("_read_point_set", &read_point_set_arrays, py::arg("path"), py::arg("value"), py::arg("columns"),
          py::arg("q_component"), py::arg("level"), py::arg("error"));
    m.def("_read_multiblock", &read_blocks, py::arg("paths"), py::arg("value"), py::arg("q_component"));
}

}  // namespace meshless::python
