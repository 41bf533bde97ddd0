// VTK XML multiblock (.vtm, vtkMultiBlockDataSet) writer: the blocks of a multiblock grid as
// StructuredGrid pieces (formats/vts_writer.hpp) plus the .vtm that lists them, the way ParaView
// saves a multiblock data set (dissertation chapter 4: overlapping / semi-conforming /
// non-conforming grids, written by `meshless split`).
//
// Files: for PREFIX.vtm the pieces go to the folder PREFIX/ beside it (created if missing) as
// PREFIX/PREFIX_<b>.vts, b = block index; the .vtm (VTK XML version 1.0) has one
// <DataSet index="b" name=BLOCK-NAME file="PREFIX/PREFIX_b.vts"/> per block, paths relative to the
// .vtm's folder. Each file is written atomically; the .vtm is written last, so an interrupted
// split leaves at worst pieces without a .vtm, never a .vtm naming a missing or partial piece.
// Returns the piece paths written. Throws IoError naming the path (folder cannot be created, a
// write fails), InvalidArgument when `path` does not end in .vtm or the multiblock has no block.
// Thread-safety: reentrant for different paths.
#pragma once
#include <string>
#include <vector>

#include "kernels/structured_block.hpp"

namespace meshless {

std::vector<std::string> write_vtm(const std::string& path, const Multiblock& mb);

}  // namespace meshless
