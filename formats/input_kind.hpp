// Which of the isosurface inputs a command's positional arguments name, from the files themselves
// (formats/multiblock_reader.hpp, formats/point_set_reader.hpp, formats/volume_reader.hpp): the
// blocks of a multiblock/AMR grid (dissertation chapter 4), one scattered point set (chapter 5),
// or else a volume (chapter 3). Reads at most the files' heads; nothing throws.
#pragma once
#include <string>
#include <vector>

namespace meshless {

/// True when the paths name blocks: one that looks like a multiblock file, or several inputs the
/// first of which is not a volume (a volume command then reports the extra argument).
bool names_blocks(const std::vector<std::string>& paths);

/// True when the paths name one scattered point set (not blocks, not a volume). raw_dims: the raw
/// volume's dimensions were given, so a .raw without the name convention is a volume.
bool names_scattered_points(const std::vector<std::string>& paths, bool raw_dims);

}  // namespace meshless
