// The descriptions of the costly builds saved as files (docs/architecture.md "Costly builds are
// files") for stream/file_info.hpp: fitted fields (.mlf, formats/field_file.hpp) and cluster binary
// trees (.mlh, formats/cluster_tree_file.hpp, dissertation chapter 6), each read and validated
// whole, then described as lines on `out`.
// Throws what the readers throw (FormatError, IoError). Thread-safety: reentrant (distinct `out`).
#pragma once
#include <cstdio>
#include <string>

namespace meshless {

/// Field kind, parameters, merge, the data it was fitted to (count, identity hash, bounds, value),
/// the build's statistics, memory when loaded, sections.
void describe_field_file(const std::string& path, std::FILE* out);
/// Depth, nodes, splits, skipped splits, error reached, parameters and the LOD sizes per level and
/// per error threshold (dissertation sections 6.3-6.5).
void describe_cluster_tree(const std::string& path, std::FILE* out);

}  // namespace meshless
