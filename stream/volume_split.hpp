// The split recipe, what `meshless split` runs (and any other front end): a regular volume written
// as the multiblock and AMR layouts of dissertation chapter 4 (Figure 4.3; section 4.5's test sets;
// kernels/multiblock_split.hpp has the exact definitions), with the lines that describe the pieces.
// Output: PREFIX.vtm + PREFIX/PREFIX_<b>.vts (VTK XML StructuredGrid pieces), or for the amr layout
// PREFIX.vthb + PREFIX/PREFIX_<n>.vti (ImageData with CellData); every file atomic, the index last.
// Units: world coordinates; counts of nodes and cells.
// Throws InvalidArgument from the splitters (parameters out of their domain), IoError from the writers.
#pragma once
#include <cstdio>
#include <string>

#include "kernels/grid.hpp"
#include "kernels/multiblock_split.hpp"

namespace meshless {

struct VolumeSplitOptions {
    SplitLayout layout = SplitLayout::overlapping;
    SplitParams split;             ///< overlapping / rotated: blocks and overlap
    AmrParams amr;                 ///< amr: isovalue and tile
    std::string name = "scalars";  ///< the scalar array's name in the pieces
};

/// Splits `v` as `o` says, writes the pieces and the index to `out` (.vtm, or .vthb for amr) and
/// writes to `report` one line per block ("  NAME: XxYxZ nodes") or AMR level ("  level L: N boxes,
/// C cells, spacing S"), then "wrote OUT and N pieces (... in all)".
void write_volume_split(const Volume& v, const VolumeSplitOptions& o, const std::string& out, std::FILE* report);

}  // namespace meshless
