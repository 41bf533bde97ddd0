// Structured VTK XML pieces read with their lattice kept (dissertation chapter 4: overlapping
// curvilinear grids and AMR boxes as blocks): ImageData (.vti), StructuredGrid (.vts) and
// RectilinearGrid (.vtr). Every <Piece> becomes a StructuredBlock; the building block of the
// multiblock (.vtm) and AMR (.vthb) readers (formats/vtk_multiblock.hpp).
//
// Node positions: ImageData Origin + Direction * ((Extent lo + ijk) * Spacing); StructuredGrid
// the <Points> array (3 components); RectilinearGrid the three <Coordinates> arrays.
// The scalar: options.value_name names a PointData or CellData array (PointData first); without
// it, the PointData Scalars attribute, then the CellData Scalars attribute, then the first
// one-component PointData array, then the first one-component CellData array (vtkGhostType and
// vtkValidPointMask are never chosen by default). A chosen array with several components is refused
// with the list of scalar arrays. Point data: the block's nodes are the points. Cell data: the
// block's nodes are the cell centres (cell_centred = true; centre = mean of the cell's 8 corner
// points; dims = cells per axis, an axis of one point counts one cell).
// A vtkGhostType array of the same centring blanks the HIDDENPOINT (0x02) points / HIDDENCELL (0x08)
// cells (valid = 0, counted in `blanked`). NaN/Inf positions or values: valid = 0, counted in
// `nonfinite` (options.strict: FormatError "PATH: piece P point|cell I: non-finite ...").
// A piece whose every node is invalid: FormatError.
// Sizes: extents are checked (hi >= lo, products without overflow) and each array's byte count is
// checked against the file size (compressed: zlib's 1032:1 bound) before anything is allocated.
// Payload formats: those of formats/vtk_xml.hpp. Bytes quoted from the file are escaped.
// Units: the file's. Throws FormatError/IoError, one line starting with the path.
// Thread-safety: reentrant.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

/// One data array of a piece: its name, components and centring.
struct VtkArrayDesc {
    std::string name;
    int components = 1;
    bool cell = false;  ///< CellData (else PointData)
};

struct VtkStructuredPiece {
    StructuredBlock block;                   ///< nodes or cell centres with the chosen scalar
    std::array<std::int64_t, 6> extent{};    ///< the piece's point extent (i0 i1 j0 j1 k0 k1)
    std::array<double, 3> origin{0, 0, 0};   ///< ImageData: Origin (world position of index 0)
    std::array<double, 3> spacing{1, 1, 1};  ///< ImageData: Spacing
    bool axis_aligned = true;                ///< ImageData: Direction is the identity
    std::uint64_t blanked = 0, nonfinite = 0;
};

struct VtkStructuredFile {
    std::string type;                    ///< "ImageData", "StructuredGrid" or "RectilinearGrid"
    std::vector<VtkArrayDesc> arrays;    ///< every PointData and CellData array of the first piece
    std::string value_name;              ///< the chosen array
    bool cell = false;                   ///< the chosen array is cell data
    std::vector<VtkStructuredPiece> pieces;
};

/// Reads every piece of a .vti/.vts/.vtr file (blocks named "FILE" or "FILE piece N").
VtkStructuredFile read_vtk_structured(const std::string& path, const PointSetOptions& options);

class VtkXmlElement;

/// Checks the NumberOfComponents of every DataArray of a piece's <PointData> and <CellData>
/// (an integer 1..4096), as read_vtk_structured does, used or not: FormatError "PATH: DataArray
/// 'NAME': bad NumberOfComponents 'C'". The .vts point-set reader runs it too, so that `info` and
/// the block commands refuse the same files with the same words.
void check_vtk_array_components(const VtkXmlElement& piece, const std::string& path);

/// "name (cell, 3 components)" lists for messages and `info` (names escaped).
std::string describe_arrays(const std::vector<VtkArrayDesc>& arrays, bool scalars_only = false);

}  // namespace meshless
