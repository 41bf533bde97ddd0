// The nodes of a VTK XML UnstructuredGrid (.vtu, vtkXMLUnstructuredGridWriter) read as scattered
// points with a scalar (dissertation chapter 5: scattered data). The cells (Connectivity, offsets,
// types) are not used: every node is a point, whether or not a cell references it.
// Each <Piece> is a block {NumberOfPoints,1,1}; the <Points> DataArray (3 components, any type)
// and the PointData array chosen as for .vtp (formats/points_vtp.hpp: options.value_name, else
// <PointData Scalars=...>, else the first one-component array). Payloads: ascii, inline base64,
// appended raw/base64, zlib, UInt32/UInt64 headers, either byte order (formats/vtk_xml.hpp, the
// decoder the .vti/.vtp/.vts readers share). NaN/Inf nodes are dropped and counted as every
// point-set reader does (formats/point_set_options.hpp).
// Throws FormatError (wrong VTK type, missing Points, NumberOfPoints beyond the file, truncated or
// corrupt payloads, a compressed block claiming more than it can hold), IoError; each names the path.
// Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"

namespace meshless {

PointSet read_points_vtu(const std::string& path, const PointSetOptions& options,
                         std::vector<std::string>* notes = nullptr);

}  // namespace meshless
