// The oriented points a meshless isosurface returns (kernels/records.hpp PointRecord: position,
// unit normal toward decreasing values, splat radius, value; and, from blocks, the block each point
// was seeded in) as NumPy arrays sharing one capsule-owned buffer: points (n, 3), normals (n, 3),
// radius (n,) and values (n,) float32 are strided views of the records, block (n,) uint32.
// Nothing is copied. Throws nothing but std::bad_alloc.
#pragma once
#include <cstdint>
#include <vector>

#include "arrays.hpp"
#include "kernels/records.hpp"

namespace meshless::python {

/// A dict {"points", "normals", "radius", "values"[, "block"]}. swap_xz: the records came from a
/// volume seen with x and z swapped (VolumeArray::axes_swapped); they are swapped back in place.
py::dict point_arrays(std::vector<PointRecord>&& records, std::vector<std::uint32_t>* blocks = nullptr, bool swap_xz = false);

}  // namespace meshless::python
