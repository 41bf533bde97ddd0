// The pictures of the Python module (python/README.md): meshless.render ray casts a NumPy volume, a
// brick store or a Field over its points (stream/field_render.hpp, what `meshless render` runs);
// meshless.splat draws a PLY point set or mesh (stream/splat_picture.hpp, what `meshless splat`
// runs, the picture handed back instead of written); and PNG files in and out through the product's
// own reader and writer (formats/png_reader.hpp, formats/png_writer.hpp). Pictures are 8-bit RGB
// (height, width, 3) arrays owning the recipe's buffer (python/src/image_array.hpp). The GIL is
// released while a picture is made, read or written.
#include <pybind11/stl.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>

#include "arrays.hpp"
#include "bindings.hpp"
#include "stream/camera_request.hpp"
#include "field_object.hpp"
#include "image_array.hpp"
#include "formats/png_reader.hpp"
#include "formats/png_writer.hpp"
#include "formats/transfer_function_file.hpp"
#include "kernels/errors.hpp"
#include "kernels/transfer_function.hpp"
#include "stream/available_cpus.hpp"
#include "stream/field_render.hpp"
#include "stream/splat_picture.hpp"
#include "stream/volume_input.hpp"

namespace meshless::python {

namespace {

int thread_count(int threads) {
    if (threads < 0 || threads > 1024) throw py::value_error("threads: expected 0..1024 (0: every CPU this process may use)");
    return threads == 0 ? available_cpus() : threads;
}

template <class T>
std::optional<T> opt(const py::dict& d, const char* key) {
    if (!d.contains(key) || d[key].is_none()) return std::nullopt;
    return d[key].cast<T>();
}

CameraRequest camera_options(const py::dict& d) {
    CameraRequest o;
    o.option_prefix = "";
    const auto size = d["size"].cast<std::vector<long long>>();
    if (size.size() != 2 || size[0] < 1 || size[0] > 16384 || size[1] < 1 || size[1] > 16384)
        throw py::value_error("size: expected (width, height), 1..16384 pixels each");
    o.width = static_cast<int>(size[0]);
    o.height = static_cast<int>(size[1]);
    o.azimuth = opt<double>(d, "azimuth");
    o.elevation = opt<double>(d, "elevation");
    o.up = opt<std::string>(d, "up");
    o.view = opt<std::string>(d, "view");
    o.zoom = d["zoom"].cast<double>();
    o.ortho = d["ortho"].cast<bool>();
    return o;
}

std::optional<std::array<double, 2>> range_arg(const py::object& o, const char* what) {
    if (o.is_none()) return std::nullopt;
    const auto v = o.cast<std::vector<double>>();
    if (v.size() != 2 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !(v[0] < v[1]))
        throw py::value_error(std::string(what) + ": expected (lo, hi), finite, lo < hi");
    return std::array<double, 2>{v[0], v[1]};
}

/// The transfer function `meshless render --tf NAME [--range LO,HI]` uses: a preset over the range
/// (the data's by default), or a file of 'value r g b a' rows.
TransferFunction transfer_function(const std::string& tf, const std::optional<std::array<double, 2>>& given,
                                   const std::array<double, 2>& data_range) {
    if (is_transfer_function_preset(tf)) {
        std::array<double, 2> range = given ? *given : data_range;
        if (!(range[0] < range[1])) range = {range[0], range[0] + 1};  // constant data
        if (!std::isfinite(range[0]) || !std::isfinite(range[1])) range = {0, 1};
        return transfer_function_preset(tf, range[0], range[1]);
    }
    if (given) throw py::value_error("range applies to the transfer-function presets; " + tf + " gives its own values");
    std::error_code ec;
    if (!std::filesystem::exists(tf, ec)) {
        std::string message = "tf " + tf + ": neither a preset (";
        const char* sep = "";
        for (auto n : transfer_function_preset_names()) message.append(sep).append(n), sep = ", ";
        message.append(") nor an existing file of 'value r g b a' rows");
        throw py::value_error(message);
    }
    return read_transfer_function_file(tf);
}

/// What render() does after its input is open, as `meshless render` does it.
py::dict render_input(RenderInput& in, const py::dict& camera, const py::dict& o) {
    const CameraRequest co = camera_options(camera);
    std::vector<std::string> warnings;
    const CameraWarning warn = [&warnings](const std::string& line) { warnings.push_back(line); };
    Camera cam = request_camera(co, warn);
    if (in.volume && in.volume->frame) apply_anatomical_camera(co, *in.volume->frame, cam, warn);
    RenderOptions ro;
    ro.shade = o["shade"].cast<bool>();
    ro.no_skip = o["no_skip"].cast<bool>();
    const auto bg = triple(o["background"], "background");
    for (double c : bg)
        if (!(c >= 0 && c <= 1)) throw py::value_error("background: expected (r, g, b), components in [0, 1]");
    ro.background = bg;
    ro.step = opt<double>(o, "step");
    if (ro.step && !(*ro.step > 0 && std::isfinite(*ro.step))) throw py::value_error("step: expected a number > 0 (world units)");
    ro.ref_step = opt<double>(o, "ref_step");
    if (ro.ref_step && !(*ro.ref_step > 0 && std::isfinite(*ro.ref_step))) throw py::value_error("ref_step: expected a number > 0 (world units)");
    if (const auto b = opt<std::vector<double>>(o, "bounds")) {
        if (b->size() != 6) throw py::value_error("bounds: expected (x0, y0, z0, x1, y1, z1)");
        const auto& v = *b;
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite(v[i]) || !std::isfinite(v[i + 3]) || !(v[i] < v[i + 3]))
                throw py::value_error("bounds: expected finite x0 < x1, y0 < y1, z0 < z1");
        ro.bounds = std::array<Vec3, 2>{Vec3{v[0], v[1], v[2]}, Vec3{v[3], v[4], v[5]}};
    }
    ro.threads = thread_count(o["threads"].cast<int>());
    const TransferFunction tf = transfer_function(o["tf"].cast<std::string>(), range_arg(o["range"], "range"), in.range);
    RenderResult rr;
    {
        py::gil_scoped_release free;
        rr = render_field(in, cam, tf, ro);
    }
    py::dict out;
    out["pixels"] = image_array(std::move(rr.picture));
    out["stats"] = py::dict(py::arg("input") = in.what, py::arg("rays") = rr.stats.rays, py::arg("rays_hit") = rr.stats.rays_hit,
                            py::arg("samples") = rr.stats.samples, py::arg("skipped") = rr.stats.skipped,
                            py::arg("terminated") = rr.stats.terminated, py::arg("step") = rr.params.step,
                            py::arg("ref_step") = rr.params.ref_step, py::arg("seconds") = rr.seconds);
    out["warnings"] = warnings;
    return out;
}

py::dict render_volume(const py::array& volume, const py::object& spacing, const py::object& origin, const py::dict& camera,
                       const py::dict& o) {
    // the picture of a C-ordered array would be mirrored (its x and z swapped): one Fortran-ordered copy
    py::array a = volume;
    if (!(a.flags() & py::array::f_style) && a.ndim() == 3) a = py::module_::import("numpy").attr("asfortranarray")(a);
    const VolumeArray v = volume_view(a, triple(spacing, "spacing"), triple(origin, "origin"));
    VolumeInput vi;
    vi.path = "array";
    Volume vol;
    vol.grid = v.view.grid;
    vol.type = v.view.type;
    const std::size_t bytes = static_cast<std::size_t>(vol.grid.voxel_count()) * sample_size(vol.type);
    // the array's samples, used in place: `v.keep` holds them for the whole call (no owner to release)
    vol.bytes = SampleBytes::adopt(static_cast<std::byte*>(const_cast<void*>(v.view.data)), bytes,
                                   std::shared_ptr<void>(const_cast<void*>(v.view.data), [](void*) {}));
    vi.volume = std::move(vol);
    std::optional<RenderInput> in;
    {
        py::gil_scoped_release free;
        in.emplace(volume_render_input(std::move(vi)));
    }
    return render_input(*in, camera, o);
}

py::dict render_store(const std::string& path, std::uint64_t memory, const py::dict& camera, const py::dict& o) {
    VolumeOpenOptions vo;
    if (memory > 0) vo.memory = memory;
    vo.threads = thread_count(o["threads"].cast<int>());
    std::optional<RenderInput> in;
    {
        py::gil_scoped_release free;
        in.emplace(volume_render_input(open_volume_input(path, vo)));
    }
    return render_input(*in, camera, o);
}

py::dict render_points(const FieldObject& f, const py::array& points, const py::array& values, const py::dict& camera,
                       const py::dict& o) {
    const PointSet pts = point_set_of(points, values);
    std::optional<RenderInput> in;
    {
        py::gil_scoped_release free;
        in.emplace(points_render_input(pts, *f.field, "points"));
    }
    return render_input(*in, camera, o);
}

ColorChoice color_choice(const std::string& color, const std::string& colormap, const py::object& range, bool colorbar) {
    ColorChoice c;
    if (color == "auto") c.request = ColorRequest::automatic;
    else if (color == "value") c.request = ColorRequest::value;
    else if (color == "block") c.request = ColorRequest::block;
    else if (color == "normal") c.request = ColorRequest::normal;
    else if (color == "none") c.request = ColorRequest::none;
    else throw py::value_error("color: expected 'auto', 'value', 'block', 'normal' or 'none', got '" + color + "'");
    if (!parse_colormap(colormap, c.colormap)) throw py::value_error("colormap: expected 'viridis', 'coolwarm' or 'gray', got '" + colormap + "'");
    c.range = range_arg(range, "range");
    c.colorbar = colorbar;
    return c;
}

py::dict splat(const std::string& path, const py::dict& camera, const std::string& kernel, const std::string& shading,
               const std::string& color, const std::string& colormap, const py::object& range, bool colorbar, int threads) {
    const CameraRequest co = camera_options(camera);
    std::vector<std::string> warnings;
    std::mutex said;
    const CameraWarning warn = [&](const std::string& line) {
        const std::lock_guard<std::mutex> lock(said);
        warnings.push_back(line);
    };
    RenderSettings rs;
    rs.camera = request_camera(co, warn);
    if (kernel == "quad") rs.kernel = SplatKernel::quad;
    else if (kernel == "ewa") rs.kernel = SplatKernel::ewa;
    else throw py::value_error("kernel: expected 'quad' or 'ewa', got '" + kernel + "'");
    if (shading == "lambert") rs.shading.specular = 0;
    else if (shading != "phong") throw py::value_error("shading: expected 'phong' or 'lambert', got '" + shading + "'");
    SplatRequest r;
    r.input = path;
    r.threads = thread_count(threads);
    r.color = color_choice(color, colormap, range, colorbar);
    r.sample_projection = [&path](const StreamMeta& m) {
        const auto iso = m.get_finite("iso");
        if (!iso) throw InvalidArgument(path + ": the stream records no isovalue; project it first (meshless project)");
        return std::pair(*iso, Projection::approx);
    };
    r.anatomical_camera = [&](const AnatomicalFrame& f, Camera& c) { apply_anatomical_camera(co, f, c, warn); };
    r.warn = [&](const std::string& line) {
        const std::lock_guard<std::mutex> lock(said);
        warnings.push_back(line);
    };
    Image picture;
    r.picture = [&picture](Image&& img) { picture = std::move(img); };
    SplatReport rep;
    {
        py::gil_scoped_release free;
        rep = splat_picture(std::move(rs), r);
    }
    py::dict out;
    out["pixels"] = image_array(std::move(picture));
    out["stats"] = py::dict(py::arg("mesh") = rep.mesh, py::arg("drawn") = rep.drawn, py::arg("seconds") = rep.seconds);
    out["warnings"] = warnings;
    return out;
}

py::array read_image(const std::string& path) {
    Image img;
    {
        py::gil_scoped_release free;
        img = read_png(path);
    }
    return image_array(std::move(img));
}

void write_image(const py::array& pixels, const std::string& path) {
    const Image img = image_of(pixels);
    py::gil_scoped_release free;
    write_png(img, path);
}

/// The PNG bytes the product's writer makes of the picture (through an unlinked temporary file).
py::bytes png_bytes(const py::array& pixels) {
    const Image img = image_of(pixels);
    std::string data;
    {
        py::gil_scoped_release free;
        std::error_code ec;
        const auto dir = std::filesystem::temp_directory_path(ec);
        std::string name = (ec ? std::filesystem::path("/tmp") : dir) / "meshless-png-XXXXXX";
        const int fd = ::mkstemp(name.data());
        if (fd < 0) throw IoError(name + ": cannot create a temporary file for the PNG");
        ::close(fd);
        struct Remove {
            const std::string& path;
            ~Remove() { std::remove(path.c_str()); }
        } remove{name};
        write_png(img, name);
        std::ifstream in(name, std::ios::binary);
        data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        if (!in.good() && !in.eof()) throw IoError(name + ": cannot read the PNG back");
    }
    return py::bytes(data);
}

}  // namespace

void bind_picture(py::module_& m) {
    m.def("_render_volume", &render_volume, py::arg("volume"), py::arg("spacing"), py::arg("origin"), py::arg("camera"), py::arg("options"));
    m.def("_render_store", &render_store, py::arg("path"), py::arg("memory"), py::arg("camera"), py::arg("options"));
    m.def("_render_points", &render_points, py::arg("field"), py::arg("points"), py::arg("values"), py::arg("camera"), py::arg("options"));
    m.def("_splat", &splat, py::arg("path"), py::arg("camera"), py::arg("kernel"), py::arg("shading"), py::arg("color"),
          py::arg("colormap"), py::arg("range"), py::arg("colorbar"), py::arg("threads"));
    m.def("_read_png", &read_image, py::arg("path"));
    m.def("_write_png", &write_image, py::arg("pixels"), py::arg("path"));
    m.def("_png_bytes", &png_bytes, py::arg("pixels"));
}

}  // namespace meshless::python
