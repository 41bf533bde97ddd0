#include "point_arrays.hpp"

#include <utility>

namespace meshless::python {

py::dict point_arrays(std::vector<PointRecord>&& records, std::vector<std::uint32_t>* blocks, bool swap_xz) {
    if (swap_xz)
        for (PointRecord& r : records) {
            std::swap(r.pos[0], r.pos[2]);
            std::swap(r.normal[0], r.normal[2]);
        }
    const auto n = static_cast<py::ssize_t>(records.size());
    PointRecord* data = nullptr;
    const py::capsule base = owning_capsule(std::move(records), &data);
    constexpr py::ssize_t rec = sizeof(PointRecord), f = sizeof(float);
    static const PointRecord empty{};
    const PointRecord* r0 = data ? data : &empty;  // an empty result: a valid pointer, no element is read
    py::dict out;
    out["points"] = view_of<float>(base, r0->pos, {n, 3}, {rec, f});
    out["normals"] = view_of<float>(base, r0->normal, {n, 3}, {rec, f});
    out["radius"] = view_of<float>(base, &r0->radius, {n}, {rec});
    out["values"] = view_of<float>(base, &r0->value, {n}, {rec});
    if (blocks) {
        std::uint32_t* b = nullptr;
        const py::capsule bb = owning_capsule(std::move(*blocks), &b);
        static const std::uint32_t none = 0;
        out["block"] = view_of<std::uint32_t>(bb, b ? b : &none, {n}, {static_cast<py::ssize_t>(sizeof(std::uint32_t))});
    }
    return out;
}

}  // namespace meshless::python
