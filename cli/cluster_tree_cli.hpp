// The commands of dissertation chapter 6 (cluster binary trees): `meshless hierarchy` (build a
// .mlh), `meshless lod` (extract a level of detail) and what `meshless info` prints for a .mlh.
#pragma once
#include <string>

namespace meshless::cli {

/// `meshless info tree.mlh`: depth, nodes, splits, skipped splits, error reached, parameters and
/// the LOD sizes per level and per error threshold. Throws FormatError/IoError for a bad file.
void info_cluster_tree(const std::string& path);

}  // namespace meshless::cli
