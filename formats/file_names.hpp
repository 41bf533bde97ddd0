// File names as the tool reads them: extensions compared without case, the names of multi-file
// inputs joined for a `source` entry. Pure string work; throws nothing but std::bad_alloc.
#pragma once
#include <string>
#include <vector>

namespace meshless {

/// The extension of a path's file name, lower-cased (".raw", ".vtm"; "" when none).
std::string lower_extension(const std::string& path);
/// Whether `path` ends with `suffix` (lower-case ASCII), ignoring the case of the path's letters.
bool ends_with_ci(const std::string& path, const char* suffix);
/// The files' names (no folders) joined by ',' (the `source` of multi-file inputs).
std::string joined_names(const std::vector<std::string>& paths);

}  // namespace meshless
