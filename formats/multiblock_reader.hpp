// Multiblock grids and AMR hierarchies read with their block structure kept (dissertation chapter
// 4: overlapping curvilinear grids, sections 4.3-4.6), for the marching-cubes seed stage and the
// naive per-block marching cubes. Inputs, by extension:
// - PLOT3D .xyz/.x/.g/.bin (+ q or function file) and .p3d meta files (formats/plot3d.hpp,
//   read_plot3d_blocks): IBLANK 0 nodes are kept in the lattice with valid = 0 (Multiblock::blanked);
// - VTK XML .vts/.vti/.vtr files, each <Piece> a block (formats/vtk_structured.hpp): point data, or
//   cell data as blocks of cell centres (StructuredBlock::cell_centred);
// - .vtm (vtkMultiBlockDataSet listing .vts/.vti/.vtr pieces) and AMR hierarchies (.vthb,
//   vtkOverlappingAMR XML 1.1, and the older vtkHierarchicalBoxDataSet .vtm with group/amr_box
//   entries), pieces checked against their amr_box and level spacing (formats/vtk_multiblock.hpp);
// - anything else the point-set readers take whose blocks are complete lattices (a regular volume
//   is one block; a file whose reader dropped samples is refused).
// NaN/Inf coordinates or values: valid = 0, counted in Multiblock::nonfinite (options.strict:
// FormatError naming the file and grid/piece and point). A block whose every node is invalid:
// FormatError. Several files: blocks appended in argument order; their scalars must have one name
// (FormatError otherwise); block names get the file name in front when it is not in them already.
// Options as the point-set readers (formats/point_set_options.hpp): value_name (--value) selects
// the PLOT3D q field / VTK point or cell array, q_component, q_file, function_file, value_index,
// byte_order, allow_trailing, strict.
// Units: the files'. Throws FormatError/IoError, one line starting with the offending path; bytes
// quoted from files are escaped. InvalidArgument when `paths` is empty. Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"
#include "formats/vtk_multiblock.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

/// Reads every file as blocks, appended in argument order (block ids = their index).
Multiblock read_multiblock(const std::vector<std::string>& paths, const PointSetOptions& options = {});
/// The same, and what the first file holds beyond its blocks (arrays with their centring, AMR levels,
/// refinement ratios, origin; formats/vtk_multiblock.hpp) for `meshless info`.
Multiblock read_multiblock(const std::vector<std::string>& paths, const PointSetOptions& options,
                           MultiblockDetails& details);

/// True for files that are block inputs rather than volumes or scattered points (by extension and
/// content): .vts .vtr .vtm .vthb, PLOT3D .xyz/.x/.g/.p3d and .bin with a PLOT3D header. (read_multiblock
/// also takes .vti and regular volumes as blocks.)
bool looks_like_multiblock(const std::string& path);

}  // namespace meshless
