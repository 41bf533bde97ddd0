// meshless._core: the compiled half of the Python module `meshless` (python/meshless/__init__.py
// is the API users call; python/README.md). A thin binding over the libraries: each function runs
// the recipe the matching CLI command runs (stream/), never anything of cli/.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "kernels/errors.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
    m.doc() = "meshless: point-based isosurfaces, fields and pictures of volume data without meshing (compiled core)";
    m.attr("__version__") = MESHLESS_VERSION;  // the CMake project's version (python/CMakeLists.txt)
    // bad data (meshless::FormatError): meshless.DataError, a ValueError; I/O: OSError; bad arguments
    // (InvalidArgument, a std::invalid_argument): ValueError, pybind11's own mapping
    static py::exception<meshless::FormatError> data_error(m, "DataError", PyExc_ValueError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const meshless::FormatError& e) {
            PyErr_SetString(data_error.ptr(), e.what());
        } catch (const meshless::IoError& e) {
            PyErr_SetString(PyExc_OSError, e.what());
        }
    });
    meshless::python::bind_isosurface(m);
    meshless::python::bind_field(m);
    meshless::python::bind_mesh(m);
    meshless::python::bind_io(m);
    meshless::python::bind_picture(m);
    meshless::python::bind_hierarchy(m);
    meshless::python::bind_store(m);
    meshless::python::bind_read(m);
}
