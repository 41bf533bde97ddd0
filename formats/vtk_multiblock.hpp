// VTK XML collections read as structured blocks (dissertation chapter 4, sections 4.3-4.6:
// overlapping multiblock grids and AMR hierarchies as one set of blocks):
//
// - vtkMultiBlockDataSet (.vtm, what ParaView writes): every <DataSet file=...> in document order,
//   nested <Block>s flattened; pieces .vts/.vti/.vtr (formats/vtk_structured.hpp), paths relative
//   to the .vtm's directory; a DataSet without a file (an empty block) is skipped with a note. Block
//   names: the DataSet's name attribute, else the piece's file name.
// - AMR, vtkOverlappingAMR / vtkHierarchicalBoxDataSet XML 1.1 (.vthb): <vtkOverlappingAMR
//   origin=...> (or <vtkHierarchicalBoxDataSet>), per <Block level= spacing=> the boxes
//   <DataSet index= amr_box="i0 i1 j0 j1 k0 k1" file=...> (cell index boxes, inclusive).
// - AMR, the older vtkHierarchicalBoxDataSet .vtm (XML 0.1): <RefinementRatio level= refinement=>
//   and <DataSet group= dataset= amr_box= file=> entries; origin and level spacings come from the
//   pieces and must agree among them and with the declared refinement ratios.
//   AMR pieces are ImageData (.vti). Each piece is checked against its box: cells per axis (points
//   - 1; an axis of one point counts one cell) = amr_box extent, Spacing = the level's spacing,
//   piece origin (Origin + Extent lo * Spacing) = the hierarchy origin + amr_box lo * spacing
//   (tolerance 1e-3 of the spacing, 1e-5 relative for spacings: files store float32 spacings
//   beside float64 ones), and consecutive levels' spacings must differ by an integer ratio equal to a
//   declared RefinementRatio: a contradiction is a
//   FormatError naming the collection and the piece. The chosen array (options.value_name, else
//   as formats/vtk_structured.hpp chooses) must have one centring in every piece (mixed cell/point
//   centring: FormatError). Cell data: one block per box whose nodes are its cell centres
//   (cell_centred, level set); point data: the box's points as they are.
// A missing, unreadable or malformed piece: FormatError "COLLECTION: piece 'FILE' (...): <why>".
// A piece listed twice is refused (it would multiply what one file's bytes can allocate).
// A piece that is itself a collection is refused (no recursion). Bytes quoted from files escaped.
// Units: the files'. Thread-safety: reentrant.
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"
#include "formats/vtk_structured.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

/// One AMR level as read: its boxes, spacing and refinement ratio to the previous level.
struct MultiblockLevel {
    int level = 0;
    std::size_t boxes = 0;
    std::array<double, 3> spacing{0, 0, 0};
    int refinement = 0;  ///< spacing(level - 1) / spacing(level); 0 for the coarsest level
};

/// What a collection holds beyond its blocks (for `meshless info`).
struct MultiblockDetails {
    std::string description;                        ///< e.g. "VTK AMR, vtkOverlappingAMR XML 1.1"
    std::vector<VtkArrayDesc> arrays;               ///< the first piece's arrays with their centring
    bool cell = false;                              ///< the chosen array is cell data
    std::vector<MultiblockLevel> levels;            ///< AMR only, coarsest first
    std::optional<std::array<double, 3>> origin;    ///< AMR only
    std::vector<std::string> files;                 ///< the pieces read, as the collection names them (joined to its folder)
};

/// True when the file's <VTKFile type> is an AMR collection (vtkOverlappingAMR,
/// vtkHierarchicalBoxDataSet, vtkUniformGridAMR); reads only the file's first 4 KiB.
bool is_vtk_amr(const std::string& path);

/// Reads a .vtm or .vthb (multiblock or AMR, by its <VTKFile type>). Multiblock::format is "vtm",
/// "vthb" (XML 1.x AMR) or "vtm-amr" (XML 0.1 AMR); `details` (optional) is filled.
Multiblock read_vtk_collection(const std::string& path, const PointSetOptions& options,
                               MultiblockDetails* details = nullptr);

}  // namespace meshless
