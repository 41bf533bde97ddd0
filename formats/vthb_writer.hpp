// VTK XML overlapping-AMR (.vthb, vtkUniformGridAMR XML version 1.1) writer with cell-centred data:
// the 3-level hierarchy of `meshless split --layout amr` (kernels/multiblock_split.hpp), readable
// by VTK/ParaView (vtkXMLUniformGridAMRReader) and by formats/multiblock_reader.hpp.
//
// Files: for PREFIX.vthb the boxes go to PREFIX/PREFIX_<n>.vti (n counts boxes over all levels),
// each an ImageData piece (VTK XML 1.0, LittleEndian, header_type UInt64, appended raw, no
// compressor) with WholeExtent = Piece Extent = the box's point extent in its level's index space
// (amr_box lo .. hi+1), Origin = the hierarchy's origin, Spacing = the level's spacing, and one
// <CellData Scalars=NAME> Float64 array NAME (one value per cell, i fastest) — the layout of VTK's
// own HierarchicalBoxDataset.v1.1 test set. The .vthb is
//   <VTKFile type="vtkOverlappingAMR" version="1.1" ...><vtkOverlappingAMR origin="x y z"
//   grid_description="XYZ"><Block level="l" spacing="sx sy sz"><DataSet index="i"
//   amr_box="i0 i1 j0 j1 k0 k1" file="PREFIX/PREFIX_n.vti"/>...</Block>...
// (the type VTK 9's vtkXMLUniformGridAMRWriter writes; its reader also accepts the older
// "vtkHierarchicalBoxDataSet" name that the shared test file uses). Numbers are printed with 17
// significant digits (exact doubles). Every file is atomic; the .vthb is written last.
// Returns the piece paths. Throws IoError naming the path, InvalidArgument when `path` does not end
// in .vthb, a box's values disagree with its extent, or a level is outside 0..levels-1.
// Thread-safety: reentrant for different paths.
#pragma once
#include <string>
#include <vector>

#include "kernels/multiblock_split.hpp"

namespace meshless {

std::vector<std::string> write_vthb(const std::string& path, const AmrHierarchy& h);

/// One ImageData piece with cell data: `cells` cells from index `lo` of a level with the given
/// origin and spacing, values i fastest (cells product of them).
void write_vti_cells(const std::string& path, const std::array<std::int64_t, 3>& lo,
                     const std::array<std::int64_t, 3>& cells, const std::array<double, 3>& origin,
                     const std::array<double, 3>& spacing, const std::vector<double>& value,
                     const std::string& value_name);

}  // namespace meshless
