// Curvilinear grid nodes with a scalar from VTK XML StructuredGrid (.vts), read as a point set
// (connectivity dropped, dissertation chapter 5 multiblock data such as multicomb_0..2.vts).
// Each <Piece> is a block with the Extent's dims (x fastest); Points + the PointData array chosen
// as in formats/points_vtp.hpp (default: <PointData Scalars=...>, e.g. "Density"). Several files
// = several blocks: use read_point_set(std::vector<std::string>) in formats/point_set_reader.hpp.
// Throws FormatError/IoError naming the path. Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"

namespace meshless {

PointSet read_points_vts(const std::string& path, const PointSetOptions& options,
                         std::vector<std::string>* notes = nullptr);

}  // namespace meshless
