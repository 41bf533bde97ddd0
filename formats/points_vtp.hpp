// Scattered points with a scalar from VTK XML PolyData (.vtp), and the shared piece reader used
// for StructuredGrid (.vts, formats/points_vts.hpp) and UnstructuredGrid (.vtu, formats/points_vtu.hpp). Dissertation chapters 4-5 inputs.
//
// Every <Piece> becomes a block (PolyData: {NumberOfPoints,1,1}; StructuredGrid: the Extent's
// dims, x fastest as VTK stores them). Points: the <Points> DataArray (3 components, any type).
// The scalar: the PointData array named options.value_name (FormatError listing the arrays when
// absent), else the array named by <PointData Scalars=...> when it has one component, else the
// first one-component PointData array; none -> positions only. A multi-component array chosen by
// name gives its Euclidean norm. Payloads: ascii, inline base64, appended raw/base64, zlib,
// UInt32/UInt64 headers, either byte order (formats/vtk_xml.hpp).
// Throws FormatError (wrong VTK type, missing Points, size mismatches, corrupt data), IoError.
// Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"

namespace meshless {

PointSet read_points_vtp(const std::string& path, const PointSetOptions& options,
                         std::vector<std::string>* notes = nullptr);

/// The piece reader behind .vtp, .vts and .vtu: `vtk_type` is "PolyData", "StructuredGrid" or
/// "UnstructuredGrid" (read as PolyData is: NumberOfPoints per piece; its cells are counted in a
/// note and not used).
PointSet read_points_vtk_xml(const std::string& path, const std::string& vtk_type, const PointSetOptions& options,
                             std::vector<std::string>* notes = nullptr);

}  // namespace meshless
