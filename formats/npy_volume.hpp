// NumPy .npy 3-D arrays as regular volumes (np.save(path, vol)), read through the payload plan every
// raw-layout volume shares (formats/payload.hpp): map_volume maps the file (no read, no copy) when
// the dtype is a native sample type in host byte order, and the slab streamer
// (ooc/slice_source.hpp) reads it slab by slab.
// Layout: C order, shape (nz, ny, nx) with x fastest, as NumPy stores vol.shape == (nz, ny, nx);
// Fortran order (np.asfortranarray), shape (nx, ny, nz), x fastest too. dtypes (formats/npy_header.hpp):
// u1 i1 u2 i2 u4 i4 u8 i8 f4 f8 in either byte order, converted as formats/stored_type.hpp says.
// Geometry: the file has none: spacing RawOptions::spacing (default 1,1,1), origin 0.
// A 2-D array (N,3)/(N,k) is a point set (formats/points_raw.hpp); the dispatch is by the number of
// dimensions (formats/npy_header.hpp npy_ndim).
// Units: spacing in world units. Throws FormatError naming the path: the header's defects
// (formats/npy_header.hpp), a shape that is not 3-D or has a zero size, shape x itemsize overflowing,
// data shorter or longer than the shape claims; InvalidArgument for a spacing <= 0. Thread-safety: reentrant.
// Dissertation: chapter 3 input.
#pragma once
#include <string>

#include "formats/payload.hpp"

namespace meshless {

PayloadPlan plan_npy(const std::string& path, const RawOptions& raw);

}  // namespace meshless
