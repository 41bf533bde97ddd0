// The parts of the Python module `meshless._core` (python/README.md), one function per topic,
// called from module.cpp. Library errors become Python exceptions there: InvalidArgument ->
// ValueError, FormatError -> ValueError (bad data), IoError -> OSError.
#pragma once
#include <pybind11/pybind11.h>

namespace meshless::python {

void bind_isosurface(pybind11::module_& m);
void bind_field(pybind11::module_& m);
void bind_mesh(pybind11::module_& m);
void bind_io(pybind11::module_& m);
void bind_picture(pybind11::module_& m);
void bind_hierarchy(pybind11::module_& m);
void bind_store(pybind11::module_& m);
void bind_read(pybind11::module_& m);

}  // namespace meshless::python
