// NumPy arrays in and out of the meshless libraries without copying big data (the Python module,
// python/README.md):
// - volume_view: a 3-D array indexed [x, y, z] in one of the tool's sample types (uint8, int16,
//   uint16, float32, native byte order) seen in place as a VolumeView (kernels/grid.hpp). A
//   Fortran-ordered array (x fastest, as np.fromfile(f, t).reshape(nz, ny, nx).T gives) is the
//   tool's own layout; a C-ordered one is seen as the volume with x and z swapped (axes_swapped:
//   the caller swaps x and z back in what it returns). Other dtypes, byte orders and non-contiguous
//   views are converted to a Fortran-ordered float32 copy, and samples at a misaligned address (a
//   file mapped at an odd header length) to an aligned copy in the same order: the only copies.
// - owned arrays: results the libraries made in std::vectors are moved into a capsule that the
//   returned NumPy arrays share as their base, so they own the memory and nothing is copied
//   (record_field: one field of an array of records, a strided view).
// Throws ValueError (pybind11::value_error) for arrays of the wrong shape.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "kernels/grid.hpp"
#include "kernels/vec3.hpp"

namespace meshless::python {

namespace py = pybind11;

/// A volume seen by the libraries; `keep` holds the array (or its converted copy) alive.
struct VolumeArray {
    VolumeView view;
    bool axes_swapped = false;  ///< C order: the view's x is the array's z
    py::array keep;
};

/// The array as a volume with the given spacing and origin (world units, array axes order).
VolumeArray volume_view(const py::array& a, const std::array<double, 3>& spacing, const std::array<double, 3>& origin);

/// A capsule that owns `v` (moved in), for arrays that share it as their base.
template <class T>
py::capsule owning_capsule(std::vector<T>&& v, T** data) {
    auto* held = new std::vector<T>(std::move(v));
    *data = held->data();
    return py::capsule(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
}

/// An array of `shape` over memory owned by `base` (strides in bytes).
template <class T>
py::array_t<T> view_of(const py::capsule& base, const T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides) {
    return py::array_t<T>(std::move(shape), std::move(strides), data, base);
}

/// (n, 3) positions from any real array (converted to double); ValueError naming `what` otherwise.
std::vector<Vec3> vec3_rows(const py::array& a, const char* what);
/// (n,) values from any real array (converted to double); ValueError naming `what` unless n == expect.
std::vector<double> real_values(const py::array& a, std::size_t expect, const char* what);
/// Three finite numbers (a sequence of 3); ValueError naming `what` otherwise.
std::array<double, 3> triple(const py::object& o, const char* what);

}  // namespace meshless::python
