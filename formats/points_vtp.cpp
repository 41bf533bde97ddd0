#include "formats/points_vtp.hpp"

#include <cmath>
#include <filesystem>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "formats/vtk_structured.hpp"
#include "formats/vtk_xml.hpp"
#include "kernels/checked_size.hpp"

namespace meshless {

PointSet read_points_vtp(const std::string& path, const PointSetOptions& o, std::vector<std::string>* notes) {
    return read_points_vtk_xml(path, "PolyData", o, notes);
}

PointSet read_points_vtk_xml(const std::string& path, const std::string& vtk_type, const PointSetOptions& o,
                             std::vector<std::string>* notes) {
    const auto bytes = read_file_bytes(path);
    if (bytes.empty()) throw FormatError(path + ": empty file");
    const VtkXmlDocument X(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
    const VtkXmlFile& F = X.file();
    if (F.type != vtk_type)
        throw FormatError(path + ": VTK XML type '" + escape_field(F.type) + "', expected " + vtk_type);
    const VtkXmlElement top = X.root().child(vtk_type.c_str());
    if (!top.found()) throw FormatError(path + ": missing <" + vtk_type + ">");
    const bool structured = vtk_type == "StructuredGrid";
    const std::string file_name = std::filesystem::path(path).filename().string();

    PointSetBuilder b(path, o);
    std::string value_name;
    bool has_values = false, first_piece = true;
    int piece_no = 0;
    std::uint64_t polys = 0, strips = 0;  // PolyData: a surface mesh, whose vertices are read
    std::uint64_t cells = 0;              // UnstructuredGrid: cells, not used (the nodes are the points)
    for (const VtkXmlElement& piece : top.children("Piece")) {
        if (vtk_type == "PolyData") {
            const std::int64_t np = parse_int(piece.attr("NumberOfPolys", "0"), path, "NumberOfPolys");
            const std::int64_t ns = parse_int(piece.attr("NumberOfStrips", "0"), path, "NumberOfStrips");
            if (np > 0) polys += static_cast<std::uint64_t>(np);
            if (ns > 0) strips += static_cast<std::uint64_t>(ns);
        } else if (vtk_type == "UnstructuredGrid") {
            const std::int64_t nc = parse_int(piece.attr("NumberOfCells", "0"), path, "NumberOfCells");
            if (nc > 0) cells += static_cast<std::uint64_t>(nc);
        }
        std::array<std::int64_t, 3> dims{0, 1, 1};
        std::uint64_t n = 0;
        if (structured) {
            const VtkPieceExtent E = vtk_piece_extent(piece.attr("Extent", top.attr("WholeExtent")), path, piece_no);
            dims = E.dims;
            check_vtk_array_components(piece, path);  // every array, as the block commands' reader
            n = E.points;
        } else {
            const auto np = parse_int(piece.attr("NumberOfPoints", "0"), path, "NumberOfPoints");
            n = checked_count(np, path + ": NumberOfPoints of piece " + std::to_string(piece_no));
            dims = {np, 1, 1};
        }
        if (n / 8 > bytes.size())  // a compressed float triple still takes some bits
            throw FormatError(path + ": implausible point count " + std::to_string(n) + " for a " + std::to_string(bytes.size()) + "-byte file");
        // Points
        const VtkXmlElement pts = piece.child("Points");
        if (!pts.found() || pts.empty()) throw FormatError(path + ": piece " + std::to_string(piece_no) + " has no <Points>");
        const VtkXmlElement parr = pts.child("DataArray");
        if (!parr.found()) throw FormatError(path + ": <Points> without a DataArray");
        if (parr.attr("NumberOfComponents", "1") != "3")
            throw FormatError(path + ": <Points> DataArray has " + escape_field(parr.attr("NumberOfComponents", "1")) +
                              " components, expected 3");
        const std::vector<double> xyz = vtk_xml_read_array(X, parr, checked_mul(3, n, path + ": <Points> size"), path);
        // PointData
        VtkXmlElement chosen;
        int ncomp = 1;
        const VtkXmlElement pd = piece.child("PointData");
        if (pd.found() && !pd.empty()) {
            const std::vector<VtkXmlElement> arrays = pd.children("DataArray");
            auto comps = [&](const VtkXmlElement& a) {
                const std::int64_t c = parse_int(a.attr("NumberOfComponents", "1"), path, "NumberOfComponents");
                return c < 1 || c > 1024 ? 0 : static_cast<int>(c);  // 0: refused below when chosen
            };
            if (!o.value_name.empty()) {
                for (const auto& a : arrays)
                    if (a.attr("Name") == o.value_name) chosen = a;
                if (!chosen.found()) {
                    std::string s;
                    for (const auto& a : arrays) s += (s.empty() ? "" : ", ") + escape_field(a.attr("Name"));
                    throw FormatError(path + ": no PointData array '" + escape_field(o.value_name) + "' (arrays: " +
                                      (s.empty() ? "none" : s) + ")");
                }
            } else {
                const std::string want = pd.attr("Scalars");
                for (const auto& a : arrays)
                    if (!want.empty() && a.attr("Name") == want && comps(a) == 1) chosen = a;
                for (const auto& a : arrays)
                    if (!chosen.found() && comps(a) == 1) chosen = a;
            }
            if (chosen.found()) ncomp = comps(chosen);
            if (ncomp < 1)
                throw FormatError(path + ": bad NumberOfComponents in array '" + escape_field(chosen.attr("Name")) +
                                  "' (1..1024)");
        } else if (!o.value_name.empty()) {
            throw FormatError(path + ": no PointData array '" + o.value_name + "' (the piece has no PointData)");
        }
        std::vector<double> vals;
        if (chosen.found())
            vals = vtk_xml_read_array(X, chosen, checked_mul(n, static_cast<std::uint64_t>(ncomp), path + ": PointData size"), path);
        const std::string vname = chosen.found() ? chosen.attr("Name") : "";
        if (!first_piece && (vname != value_name || chosen.found() != has_values))
            throw FormatError(path + ": piece " + std::to_string(piece_no) + " has scalar '" + escape_field(vname) +
                              "', piece 0 has '" + escape_field(value_name) + "'");
        value_name = vname;
        has_values = chosen.found();
        first_piece = false;
        b.begin_block(file_name + (piece_no ? " piece " + std::to_string(piece_no) : ""), dims);
        b.reserve(b.set().pos.size() + n);
        for (std::uint64_t i = 0; i < n; ++i) {
            double v = 0;
            if (has_values) {
                if (ncomp == 1) {
                    v = vals[i];
                } else {
                    for (int c = 0; c < ncomp; ++c) v += vals[i * ncomp + c] * vals[i * ncomp + c];
                    v = std::sqrt(v);
                }
            }
            b.add(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], v, "point", i);
        }
        ++piece_no;
    }
    if (piece_no == 0) throw FormatError(path + ": no <Piece> in <" + vtk_type + ">");
    if (notes && has_values) notes->push_back("scalar: PointData array '" + value_name + "'");
    if (notes && piece_no > 1) notes->push_back(std::to_string(piece_no) + " pieces");
    if (notes && polys + strips > 0)
        notes->push_back(std::to_string(polys) + " polygons" + (strips ? ", " + std::to_string(strips) + " triangle strips" : "") +
                         ": a surface mesh, read as the points of its vertices");
    if (notes && cells > 0)
        notes->push_back(std::to_string(cells) + " cells: not used, the " + std::to_string(b.set().pos.size()) +
                         " nodes are read as scattered points");
    return b.finish(value_name, has_values);
}

}  // namespace meshless
