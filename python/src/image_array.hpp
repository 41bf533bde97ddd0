// Pictures of the Python module (meshless.Image, python/README.md) as NumPy arrays: the 8-bit RGB
// picture a recipe made (kernels/splat_rasterizer.hpp Image: row-major, top row first) moved into a
// capsule that an (height, width, 3) uint8 array shares as its base (nothing copied); and back, an
// (h, w, 3) uint8 array as an Image (copied) for the product's PNG writer (formats/png_writer.hpp).
// Throws ValueError (pybind11::value_error) for an array that is not (h, w, 3) uint8 with h, w >= 1.
#pragma once
#include "arrays.hpp"
#include "kernels/splat_rasterizer.hpp"

namespace meshless::python {

/// The picture as an (height, width, 3) uint8 array owning its pixels.
py::array image_array(Image&& img);

/// An (h, w, 3) uint8 array's pixels as an Image (one copy).
Image image_of(const py::array& pixels);

}  // namespace meshless::python
