// VTK XML StructuredGrid (.vts) writer: one block of a multiblock grid (dissertation chapter 4,
// section 4.5's multiblock test sets, written by `meshless split`), readable by VTK/ParaView
// (vtkXMLStructuredGridReader) and by formats/points_vts.hpp / formats/multiblock_reader.hpp.
//
// Layout written (VTK XML version 1.0, LittleEndian, header_type UInt64, no compressor):
//   <StructuredGrid WholeExtent="0 nx-1 0 ny-1 0 nz-1"> one <Piece> with the same Extent;
//   <PointData Scalars=NAME> one Float32 DataArray NAME (the node values; exact for uint8/int16/
//   uint16/float32 volumes), plus, when the block has invalid nodes, a UInt8 "vtkGhostType" array
//   with 0 for valid nodes and 1 (vtkDataSetAttributes::DUPLICATEPOINT) for blanked ones;
//   <Points> a Float64 3-component array (node positions, exact); all arrays format="appended"
//   in one <AppendedData encoding="raw">: per array a UInt64 byte count, then the bytes.
// Names are XML-escaped (& < > " and control bytes). Written atomically (formats/atomic_file.hpp):
// a failed or killed write leaves no file that looks complete.
// Throws IoError naming the path; InvalidArgument when the block's arrays disagree with its dims.
// Thread-safety: reentrant (one file per call).
#pragma once
#include <string>

#include "formats/vtk_xml_output.hpp"  // vtk_xml_escape, vtk_xml_append_raw

#include "kernels/structured_block.hpp"

namespace meshless {

void write_vts(const std::string& path, const StructuredBlock& block, const std::string& value_name);
}  // namespace meshless
