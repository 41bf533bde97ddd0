// The field parameter a point file recommends for itself: a level of detail written by `meshless
// lod` (kernels/cluster_lod.hpp) carries the Hardy c its points reconstruct best with, as the
// provenance line "meshless field: hardy-c-rel C" (C relative to the points' bounding-box diagonal,
// kernels/field_params.hpp) in a PLY header comment or in an XML comment before a VTP's VTKFile
// element. Every command that builds a field of those points uses it when no --hardy-c or
// --hardy-c-world is given (docs/architecture.md, "Levels of detail").
// Only the file's first 64 KiB are read; a missing, unreadable or malformed line, a C outside
// (0, 100] or another format gives nullopt (a hint, not data: nothing is refused for it).
// Thread-safety: reentrant. Throws only std::bad_alloc.
#pragma once
#include <optional>
#include <string>
#include <string_view>

namespace meshless {

/// "meshless field: hardy-c-rel C", C in the fewest of 15..17 significant digits that read back the same (the line to write).
std::string field_hint_line(double hardy_c_rel);

/// The C of a field_hint_line in `text` (the first one), or nullopt.
std::optional<double> parse_field_hint(std::string_view text);

/// The hint a .ply or .vtp file at `path` carries in its header, or nullopt.
std::optional<double> point_file_field_hint(const std::string& path);

}  // namespace meshless
