#include "arrays.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>

namespace meshless::python {

namespace {

std::optional<SampleType> native_type(const py::dtype& d) {
    if (!(d.byteorder() == '=' || d.byteorder() == '|' || d.byteorder() == '<')) return std::nullopt;
    if (d.is(py::dtype::of<std::uint8_t>())) return SampleType::u8;
    if (d.is(py::dtype::of<std::int16_t>())) return SampleType::i16;
    if (d.is(py::dtype::of<std::uint16_t>())) return SampleType::u16;
    if (d.is(py::dtype::of<float>())) return SampleType::f32;
    return std::nullopt;
}

}  // namespace

VolumeArray volume_view(const py::array& in, const std::array<double, 3>& spacing, const std::array<double, 3>& origin) {
    if (in.ndim() != 3) throw py::value_error("volume: expected a 3-D array indexed [x, y, z], got " + std::to_string(in.ndim()) + " dimensions");
    for (int a = 0; a < 3; ++a)
        if (in.shape(a) < 2) throw py::value_error("volume: every axis needs at least 2 samples (one cell), got shape " +
                                                   std::to_string(in.shape(0)) + "x" + std::to_string(in.shape(1)) + "x" + std::to_string(in.shape(2)));
    for (int a = 0; a < 3; ++a)
        if (!(spacing[static_cast<std::size_t>(a)] > 0)) throw py::value_error("spacing: expected three numbers > 0");
    VolumeArray v;
    py::array a = in;
    auto type = native_type(a.dtype());
    const bool f_order = a.flags() & py::array::f_style, c_order = a.flags() & py::array::c_style;
    if (!type || !(f_order || c_order)) {  // the one copy: other dtypes, byte orders, strided views
        a = py::array_t<float, py::array::f_style | py::array::forcecast>::ensure(in);
        if (!a) throw py::value_error("volume: expected an array of real numbers");
        type = SampleType::f32;
    }
    // samples at an address that is not a multiple of their size (a file mapped at an odd header
    // length, np.frombuffer at an odd offset): the kernels load whole samples, so they get an aligned
    // copy in the same order (a NumPy copy is aligned)
    if (reinterpret_cast<std::uintptr_t>(a.data()) % static_cast<std::uintptr_t>(a.itemsize()) != 0)
        a = py::module_::import("numpy").attr("array")(a, py::arg("copy") = true,
                                                        py::arg("order") = (a.flags() & py::array::f_style) ? "F" : "C");
    v.keep = a;
    v.view.data = a.data();
    v.view.type = *type;
    const bool fortran = a.flags() & py::array::f_style;
    v.axes_swapped = !fortran;
    for (int i = 0; i < 3; ++i) {
        const int src = fortran ? i : 2 - i;  // C order: the view's x is the array's last axis
        v.view.grid.dims[static_cast<std::size_t>(i)] = a.shape(src);
        v.view.grid.spacing[static_cast<std::size_t>(i)] = spacing[static_cast<std::size_t>(src)];
        v.view.grid.origin[static_cast<std::size_t>(i)] = origin[static_cast<std::size_t>(src)];
    }
    validate_grid(v.view.grid, "volume");
    return v;
}

std::vector<Vec3> vec3_rows(const py::array& in, const char* what) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(in);
    if (!a || a.ndim() != 2 || a.shape(1) != 3)
        throw py::value_error(std::string(what) + ": expected an (n, 3) array of real numbers");
    const auto r = a.unchecked<2>();
    std::vector<Vec3> out(static_cast<std::size_t>(a.shape(0)));
    for (py::ssize_t i = 0; i < a.shape(0); ++i) out[static_cast<std::size_t>(i)] = Vec3{r(i, 0), r(i, 1), r(i, 2)};
    return out;
}

std::vector<double> real_values(const py::array& in, std::size_t expect, const char* what) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(in);
    if (!a || a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != expect)
        throw py::value_error(std::string(what) + ": expected a 1-D array of " + std::to_string(expect) + " real numbers");
    return std::vector<double>(a.data(), a.data() + a.shape(0));
}

std::array<double, 3> triple(const py::object& o, const char* what) {
    const auto s = o.cast<std::vector<double>>();
    if (s.size() != 3 || !std::isfinite(s[0]) || !std::isfinite(s[1]) || !std::isfinite(s[2]))
        throw py::value_error(std::string(what) + ": expected three finite numbers");
    return {s[0], s[1], s[2]};
}

}  // namespace meshless::python
