// Point sets to files in the Python module (python/README.md; read_points is bind_read.cpp's):
// write_points writes a PointSet's oriented points through the sink `meshless isosurface -o` writes with (stream/point_file_sink.hpp PointFileSink: PLY, binary
// little endian, x y z nx ny nz radius value [block], or VTK XML PolyData by extension), atomically;
// write_point_set writes scattered points and values as `meshless lod` and `sample` do
// (formats/point_set_writer.hpp: .ply, .csv, .vtp); info describes any file the tool reads or
// writes, as `meshless info` does (stream/file_info.hpp).
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "arrays.hpp"
#include "bindings.hpp"
#include "formats/geometry_format.hpp"
#include "formats/ply_points.hpp"
#include "formats/point_set_writer.hpp"
#include "stream/point_file_sink.hpp"
#include "stream/file_info.hpp"
#include "point_arrays.hpp"

namespace meshless::python {

namespace {

void write_points(const std::string& path, const py::array& points, const py::array& normals, const py::array& radius,
                  const py::array& values, const py::object& block, const py::object& comments) {
    const std::optional<GeometryFormat> format = geometry_format_of(path);
    if (!format)
        throw py::value_error(path + ": oriented points are written to a .ply or .vtp file (the outputs of meshless isosurface -o)");
    const auto p = py::array_t<float, py::array::forcecast>::ensure(points), n = py::array_t<float, py::array::forcecast>::ensure(normals);
    const auto r = py::array_t<float, py::array::forcecast>::ensure(radius), v = py::array_t<float, py::array::forcecast>::ensure(values);
    if (!p || p.ndim() != 2 || p.shape(1) != 3) throw py::value_error("points: expected an (n, 3) array");
    const py::ssize_t count = p.shape(0);
    if (!n || n.ndim() != 2 || n.shape(0) != count || n.shape(1) != 3) throw py::value_error("normals: expected an (n, 3) array");
    if (!r || r.ndim() != 1 || r.shape(0) != count) throw py::value_error("radius: expected an (n,) array");
    if (!v || v.ndim() != 1 || v.shape(0) != count) throw py::value_error("values: expected an (n,) array");
    std::vector<PointRecord> rec(static_cast<std::size_t>(count));
    const auto P = p.unchecked<2>(), N = n.unchecked<2>();
    const auto R = r.unchecked<1>(), V = v.unchecked<1>();
    for (py::ssize_t i = 0; i < count; ++i) {
        PointRecord& x = rec[static_cast<std::size_t>(i)];
        for (int a = 0; a < 3; ++a) x.pos[a] = P(i, a), x.normal[a] = N(i, a);
        x.radius = R(i);
        x.value = V(i);
    }
    std::vector<std::uint32_t> ids;
    if (!block.is_none()) {
        const auto b = py::array_t<std::uint32_t, py::array::forcecast>::ensure(block);
        if (!b || b.ndim() != 1 || b.shape(0) != count) throw py::value_error("block: expected an (n,) array of block ids");
        ids.assign(b.data(), b.data() + count);
    }
    // the comments given (a point set read back keeps what the command recorded: the isovalue, the
    // surface's bounds that frame its pictures), else the one line that says what the file holds
    std::vector<std::string> lines;
    if (!comments.is_none()) lines = comments.cast<std::vector<std::string>>();
    for (const std::string& c : lines)
        if (c.find_first_of("\r\n") != std::string::npos) throw py::value_error("comments: one line each (no newlines)");
    if (lines.empty())
        lines = {block.is_none() ? "meshless oriented point set: x y z, unit normal, splat radius, value"
                                 : "meshless oriented point set: x y z, unit normal, splat radius, value, block"};
    py::gil_scoped_release free;
    // the CLI's sink, fed batches of at most kMaxBatchRecords as the graphs feed it
    PointFileSink sink(path, *format, lines, VtpOptions{}, /*with_blocks=*/!block.is_none());
    std::uint64_t seq = 0;
    for (std::size_t at = 0; at < rec.size(); at += kMaxBatchRecords) {
        const std::size_t n = std::min<std::size_t>(kMaxBatchRecords, rec.size() - at);
        Batch b;
        b.seq = seq++;
        b.kind = RecordKind::point;
        b.points.assign(rec.begin() + static_cast<std::ptrdiff_t>(at), rec.begin() + static_cast<std::ptrdiff_t>(at + n));
        if (!ids.empty()) b.point_block.assign(ids.begin() + static_cast<std::ptrdiff_t>(at), ids.begin() + static_cast<std::ptrdiff_t>(at + n));
        sink.consume(std::move(b));
    }
    sink.finish();
}

/// Scattered points and values written by extension (.ply, .csv, .vtp) as `meshless lod -o` writes them.
void write_scattered(const std::string& path, const py::array& points, const py::array& values, const std::string& value_name,
                     bool has_values, const std::vector<std::string>& comments) {
    if (path == "-") throw py::value_error("save: give a file's path");
    if (!point_set_output_name(path))
        throw py::value_error(path + ": points with values are written to a .ply, .csv or .vtp file");
    PointSet ps;
    ps.pos = vec3_rows(points, "points");
    ps.value = real_values(values, ps.pos.size(), "values");
    ps.value_name = value_name;
    ps.has_values = has_values;
    ps.blocks.push_back(PointSetBlock{"points", {static_cast<std::int64_t>(ps.pos.size()), 1, 1}, 0, ps.pos.size()});
    for (const std::string& c : comments)
        if (c.find_first_of("\r\n") != std::string::npos) throw py::value_error("comments: one line each (no newlines)");
    py::gil_scoped_release free;
    write_point_set(path, ps, comments);
}

/// The report `meshless info PATH [--value-range]` prints, as a string (the same bytes).
std::string info(const std::string& path, bool value_range) {
    if (path == "-") throw py::value_error("info: give a file's path (standard input is the CLI's)");
    FileInfoOptions o;
    o.value_range = value_range;
    char* text = nullptr;
    std::size_t size = 0;
    struct Buffer {  // freed on every path, after the stream that fills it is closed
        char*& text;
        ~Buffer() { std::free(text); }
    } buffer{text};
    {
        std::FILE* out = open_memstream(&text, &size);
        if (!out) throw std::bad_alloc();
        const std::unique_ptr<std::FILE, int (*)(std::FILE*)> closer(out, &std::fclose);
        py::gil_scoped_release free;
        describe_file(path, o, out);
    }  // closed: text and size final
    return std::string(text ? text : "", size);
}

}  // namespace

void bind_io(py::module_& m) {
    m.def("_info", &info, py::arg("path"), py::arg("value_range"));
    m.def("_write_points", &write_points, py::arg("path"), py::arg("points"), py::arg("normals"), py::arg("radius"),
          py::arg("values"), py::arg("block"), py::arg("comments") = py::none());
    m.def("_write_point_set", &write_scattered, py::arg("path"), py::arg("points"), py::arg("values"), py::arg("value_name"),
          py::arg("has_values"), py::arg("comments"));
}

}  // namespace meshless::python
