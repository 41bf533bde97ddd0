// Scattered points from headerless binary records and NumPy .npy arrays (dissertation chapters
// 4-5 inputs).
//
// Raw: float32 records x,y,z,value (16 bytes, as VTK's Particles.raw) or x,y,z (12 bytes, when
// options.columns is "x,y,z"; positions only). Byte order: options.byte_order, else detected:
// the order in which more numbers are plausible (finite, zero or 1e-12 < |v| < 1e12) wins, ties
// little endian; a forced order whose numbers are implausible while the other order's are all
// plausible is refused ("looks big-endian"); with the order detected, a file whose non-zero
// coordinates are not 90 % plausible (a raw volume read without --dims) is refused. A size that is not a whole number of records is
// refused (trailing bytes) unless allow_trailing.
// NumPy (the header: formats/npy_header.hpp): versions 1-3, dtype <f4 >f4 <f8 >f8, a 2-D shape
// (3-D arrays are volumes, formats/npy_volume.hpp): (N,3) (positions only, has_values = false)
// or (N,k>=4) (value = column options.value_index, default 3), C or Fortran order; bytes after
// the array are refused unless allow_trailing.
// Throws FormatError/IoError naming the path. Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"

namespace meshless {

PointSet read_points_raw(const std::string& path, const PointSetOptions& options,
                         std::vector<std::string>* notes = nullptr);
PointSet read_points_npy(const std::string& path, const PointSetOptions& options,
                         std::vector<std::string>* notes = nullptr);

}  // namespace meshless
