// Multiblock grids and AMR hierarchies read with their block structure kept (dissertation chapter
// 4: overlapping curvilinear grids, sections 4.3-4.6), for the marching-cubes seed stage and the
// naive per-block marching cubes. Inputs: PLOT3D xyz (+ q or function file; IBLANK 0 nodes kept
// and marked invalid), VTK XML StructuredGrid pieces (.vts; several files = several blocks), VTK XML
// multiblock .vtm listing .vts/.vti/.vtr pieces, and AMR hierarchies (.vthb, vtkUniformGridAMR XML
// 1.1, and the vtkHierarchicalBoxDataSet .vtm with group/amr_box entries) whose cell data become
// blocks of cell centres (StructuredBlock::cell_centred). A regular volume is one block.
// Options as the point-set readers (formats/point_set_options.hpp): value_name (--value) selects
// the PLOT3D q field / VTK array, q_component, function_file, byte_order, allow_trailing; strict
// refuses NaN/Inf instead of marking the node invalid.
// Units: the files'. Throws FormatError/IoError, one line starting with the offending path.
// InvalidArgument when `paths` is empty. Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

/// Reads every file as blocks, appended in argument order (block ids = their index).
Multiblock read_multiblock(const std::vector<std::string>& paths, const PointSetOptions& options = {});

/// True for files read_multiblock takes as blocks (by extension and content): .vts .vtm .vthb,
/// PLOT3D .xyz/.x/.bin/.p3d.
bool looks_like_multiblock(const std::string& path);

}  // namespace meshless
