#include "formats/oriented_points_vtp.hpp"

#include <cmath>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "formats/vtk_xml.hpp"
#include "kernels/checked_size.hpp"

namespace meshless {

namespace {

/// The comments before the root element, with the writer's `\xNN` escapes undone.
std::vector<std::string> prolog_comments(std::string_view text) {
    std::vector<std::string> out;
    const std::string_view prolog = text.substr(0, text.find("<VTKFile"));
    for (std::size_t at = prolog.find("<!--"); at != std::string_view::npos; at = prolog.find("<!--", at + 4)) {
        const std::size_t close = prolog.find("-->", at + 4);
        if (close == std::string_view::npos) break;
        std::string_view c = prolog.substr(at + 4, close - at - 4);
        // the writer's framing: "<!-- " TEXT [" " after a final '-'] " -->"
        if (!c.empty() && c.front() == ' ') c.remove_prefix(1);
        if (!c.empty() && c.back() == ' ') c.remove_suffix(1);
        if (c.size() >= 2 && c.back() == ' ' && c[c.size() - 2] == '-') c.remove_suffix(1);
        std::string s;
        for (std::size_t i = 0; i < c.size(); ++i) {
            const auto hex = [](char h) { return h >= '0' && h <= '9' ? h - '0' : h >= 'a' && h <= 'f' ? h - 'a' + 10 : -1; };
            if (c[i] == '\\' && i + 3 < c.size() && c[i + 1] == 'x' && hex(c[i + 2]) >= 0 && hex(c[i + 3]) >= 0) {
                s += static_cast<char>(hex(c[i + 2]) * 16 + hex(c[i + 3]));
                i += 3;
            } else {
                s += c[i];
            }
        }
        out.push_back(std::move(s));
    }
    return out;
}

/// The names of a PointData's arrays, escaped, for messages.
std::string array_names(const std::vector<VtkXmlElement>& arrays) {
    std::string s;
    for (const auto& a : arrays) s += (s.empty() ? "" : ", ") + escape_field(a.attr("Name"));
    return s.empty() ? "none" : s;
}

}  // namespace

OrientedPointsVtp read_oriented_points_vtp(const std::string& path) {
    const auto bytes = read_file_bytes(path);
    if (bytes.empty()) throw FormatError(path + ": empty file");
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    const VtkXmlDocument X(text, path);
    if (X.file().type != "PolyData") throw FormatError(path + ": VTK XML type '" + escape_field(X.file().type) + "', expected PolyData");
    const VtkXmlElement top = X.root().child("PolyData");
    if (!top.found()) throw FormatError(path + ": missing <PolyData>");
    OrientedPointsVtp out;
    out.comments = prolog_comments(text);
    int piece_no = 0;
    for (const VtkXmlElement& piece : top.children("Piece")) {
        const std::string where = path + ": piece " + std::to_string(piece_no);
        for (const char* cells : {"NumberOfPolys", "NumberOfStrips"})
            if (parse_int(piece.attr(cells, "0"), path, cells) > 0)
                throw FormatError(where + " is a surface mesh (" + cells + " > 0): splat draws meshes from .ply files (meshless mc -o mesh.ply)");
        const std::uint64_t n = checked_count(parse_int(piece.attr("NumberOfPoints", "0"), path, "NumberOfPoints"), where + ": NumberOfPoints");
        if (n / 8 > bytes.size())  // a compressed float triple still takes some bits
            throw FormatError(where + ": implausible point count " + std::to_string(n) + " for a " + std::to_string(bytes.size()) + "-byte file");
        const VtkXmlElement parr = piece.child("Points").child("DataArray");
        if (!parr.found()) throw FormatError(where + " has no <Points> DataArray");
        if (parr.attr("NumberOfComponents", "1") != "3")
            throw FormatError(where + ": <Points> DataArray has " + escape_field(parr.attr("NumberOfComponents", "1")) + " components, expected 3");
        const VtkXmlElement pd = piece.child("PointData");
        const std::vector<VtkXmlElement> arrays = pd.children("DataArray");
        const auto named = [&](const std::string& name) {
            for (const auto& a : arrays)
                if (!name.empty() && a.attr("Name") == name) return a;
            return VtkXmlElement();
        };
        const auto with_components = [&](const VtkXmlElement& a, const char* what, const char* comps) {
            if (!a.found()) return;
            if (a.attr("NumberOfComponents", "1") != comps)
                throw FormatError(where + ": the " + what + " array '" + escape_field(a.attr("Name")) + "' has " +
                                  escape_field(a.attr("NumberOfComponents", "1")) + " components, expected " + comps);
        };
        VtkXmlElement normals = named(pd.attr("Normals"));
        if (!normals.found()) normals = named("Normals");
        const VtkXmlElement radius = named("radius");
        VtkXmlElement value = named("value");
        if (!value.found()) value = named(pd.attr("Scalars"));
        if (!normals.found() || !radius.found())
            throw FormatError(where + ": splat draws oriented points, which need a 3-component Normals and a 'radius' point array "
                                      "(as meshless isosurface -o points.vtp writes them); the arrays here: " + array_names(arrays));
        with_components(normals, "normals", "3");
        with_components(radius, "radius", "1");
        with_components(value, "value", "1");
        const std::uint64_t n3 = checked_mul(3, n, where + ": array size");
        const std::vector<double> xyz = vtk_xml_read_array(X, parr, n3, path);
        const std::vector<double> nrm = vtk_xml_read_array(X, normals, n3, path);
        const std::vector<double> rad = vtk_xml_read_array(X, radius, n, path);
        const std::vector<double> val = value.found() ? vtk_xml_read_array(X, value, n, path) : std::vector<double>(n, 0.0);
        out.points.reserve(out.points.size() + n);
        for (std::uint64_t i = 0; i < n; ++i) {
            PointRecord p{};
            double len2 = 0;
            bool finite = std::isfinite(rad[i]) && rad[i] > 0 && std::isfinite(val[i]);
            for (int a = 0; a < 3; ++a) {
                p.pos[a] = static_cast<float>(xyz[3 * i + a]);
                finite = finite && std::isfinite(p.pos[a]) && std::isfinite(nrm[3 * i + a]);
                len2 += nrm[3 * i + a] * nrm[3 * i + a];
            }
            p.radius = static_cast<float>(rad[i]);
            p.value = static_cast<float>(val[i]);
            if (!finite || !(len2 > 0) || !std::isfinite(len2) || !std::isfinite(p.radius) || !std::isfinite(p.value)) {
                ++out.dropped;
                continue;
            }
            // unit normals (as the writer stored them) are kept bit for bit, others made unit length
            const double inv = std::abs(len2 - 1) < 1e-6 ? 1.0 : 1 / std::sqrt(len2);
            for (int a = 0; a < 3; ++a) p.normal[a] = static_cast<float>(nrm[3 * i + a] * inv);
            out.points.push_back(p);
        }
        ++piece_no;
    }
    if (piece_no == 0) throw FormatError(path + ": no <Piece> in <PolyData>");
    return out;
}

}  // namespace meshless
