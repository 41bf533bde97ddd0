// The file formats of the geometry outputs (oriented point sets, triangle meshes): PLY
// (formats/ply_points.hpp, formats/ply_mesh.hpp; MeshLab, ParaView, VTK) and VTK XML PolyData
// (formats/vtp_writer.hpp; ParaView, VTK). Outputs are chosen by extension (cli/common.hpp
// geometry_output_format), with --format overriding it for "-" or other names.
// Thread-safety: pure functions.
#pragma once
#include <optional>
#include <string>

namespace meshless {

enum class GeometryFormat { ply, vtp };

inline const char* to_string(GeometryFormat f) { return f == GeometryFormat::vtp ? "vtp" : "ply"; }

/// "ply" / "vtp" -> the format; nullopt otherwise.
inline std::optional<GeometryFormat> parse_geometry_format(const std::string& s) {
    if (s == "ply") return GeometryFormat::ply;
    if (s == "vtp") return GeometryFormat::vtp;
    return std::nullopt;
}

/// The format a path's extension names (".ply", ".vtp", any case); nullopt for other names.
inline std::optional<GeometryFormat> geometry_format_of(const std::string& path) {
    const auto dot = path.rfind('.');
    const auto slash = path.rfind('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return std::nullopt;
    std::string e = path.substr(dot + 1);
    for (char& c : e) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    return parse_geometry_format(e);
}

}  // namespace meshless
