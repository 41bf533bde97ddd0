#include "image_array.hpp"

#include <cstring>

namespace meshless::python {

py::array image_array(Image&& img) {
    const py::ssize_t h = img.height, w = img.width;
    std::uint8_t* data = nullptr;
    const py::capsule base = owning_capsule(std::move(img.rgb), &data);
    return view_of<std::uint8_t>(base, data, {h, w, 3}, {3 * w, 3, 1});
}

Image image_of(const py::array& pixels) {
    const auto a = py::array_t<std::uint8_t, py::array::c_style>::ensure(pixels);
    if (!a || !pixels.dtype().is(py::dtype::of<std::uint8_t>()) || a.ndim() != 3 || a.shape(2) != 3 || a.shape(0) < 1 ||
        a.shape(1) < 1 || a.shape(0) > 16384 || a.shape(1) > 16384)
        throw py::value_error("pixels: expected an (height, width, 3) uint8 array, 1..16384 pixels a side");
    Image img;
    img.height = static_cast<int>(a.shape(0));
    img.width = static_cast<int>(a.shape(1));
    img.rgb.resize(static_cast<std::size_t>(a.size()));
    std::memcpy(img.rgb.data(), a.data(), img.rgb.size());
    return img;
}

}  // namespace meshless::python
