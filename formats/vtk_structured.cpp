#include "formats/vtk_structured.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>

#include "formats/binary_file.hpp"
#include "formats/ply.hpp"
#include "formats/vtk_xml.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

std::string esc(const std::string& s) { return ply_escape(s, 96); }

bool mul_ok(std::uint64_t a, std::uint64_t b, std::uint64_t& out) { return !__builtin_mul_overflow(a, b, &out); }

struct Cand {
    VtkXmlElement tag;
    VtkArrayDesc desc;
};

int components_of(const VtkXmlElement& a, const std::string& path) {
    const std::string c = a.attr("NumberOfComponents", "1");
    int n = 0;
    auto r = std::from_chars(c.data(), c.data() + c.size(), n);
    if (r.ec != std::errc() || r.ptr != c.data() + c.size() || n < 1 || n > 4096)
        throw FormatError(path + ": DataArray '" + esc(a.attr("Name")) + "': bad NumberOfComponents '" + esc(c) + "'");
    return n;
}

// The DataArrays of a <PointData>/<CellData> section of the piece (none when absent).
std::vector<Cand> section_arrays(const VtkXmlElement& piece, const char* section, bool cell, const std::string& path,
                                 std::string& scalars) {
    std::vector<Cand> out;
    const VtkXmlElement s = piece.child(section);
    if (!s.found()) return out;
    scalars = s.attr("Scalars");
    for (const VtkXmlElement& a : s.children("DataArray")) {
        out.push_back(Cand{a, VtkArrayDesc{a.attr("Name"), components_of(a, path), cell}});
        if (out.size() > 100000) throw FormatError(path + ": more than 100000 arrays in <" + section + ">");
    }
    return out;
}

bool hidden_name(const std::string& n) { return n == "vtkGhostType" || n == "vtkValidPointMask"; }

const Cand& choose(const std::vector<Cand>& all, const std::string& pd_scalars, const std::string& cd_scalars,
                   const PointSetOptions& o, const std::string& path) {
    std::vector<VtkArrayDesc> descs;
    for (const auto& c : all) descs.push_back(c.desc);
    const Cand* chosen = nullptr;
    if (!o.value_name.empty()) {
        for (const auto& c : all)
            if (!chosen && c.desc.name == o.value_name) chosen = &c;
        if (!chosen)
            throw FormatError(path + ": no PointData or CellData array '" + esc(o.value_name) + "' (arrays: " +
                              describe_arrays(descs) + ")");
        if (chosen->desc.components != 1)
            throw FormatError(path + ": array '" + esc(o.value_name) + "' has " + std::to_string(chosen->desc.components) +
                              " components; a block input needs a scalar (scalar arrays: " + describe_arrays(descs, true) +
                              ")");
        return *chosen;
    }
    for (const auto& c : all)
        if (!chosen && !c.desc.cell && !pd_scalars.empty() && c.desc.name == pd_scalars && c.desc.components == 1) chosen = &c;
    for (const auto& c : all)
        if (!chosen && c.desc.cell && !cd_scalars.empty() && c.desc.name == cd_scalars && c.desc.components == 1) chosen = &c;
    for (int cell = 0; cell < 2 && !chosen; ++cell)
        for (const auto& c : all)
            if (!chosen && c.desc.cell == (cell == 1) && c.desc.components == 1 && !hidden_name(c.desc.name)) chosen = &c;
    if (!chosen)
        throw FormatError(path + ": no scalar PointData or CellData array (arrays: " + describe_arrays(descs) + ")");
    return *chosen;
}

// Refuses an array whose payload cannot fit the file before it is decoded (and allocated).
void check_fits(const VtkXmlElement& a, std::uint64_t count, const VtkXmlFile& F, std::size_t file_bytes,
                const std::string& path, const std::string& what) {
    const std::string t = a.attr("type");
    const auto st = vtk_xml_type(t);
    if (!st) throw FormatError(path + ": " + what + " DataArray '" + esc(a.attr("Name")) + "' has unsupported type '" + esc(t) + "'");
    std::uint64_t bytes = 0;
    const std::string format = a.attr("format");
    const std::uint64_t per = format == "ascii" ? 1 : stored_size(*st);  // an ascii value takes one byte at least
    const std::uint64_t limit = F.compressed && format != "ascii" ? static_cast<std::uint64_t>(file_bytes) * 1032 + 4096
                                                                  : static_cast<std::uint64_t>(file_bytes);
    if (!mul_ok(count, per, bytes) || bytes > limit)
        throw FormatError(path + ": " + what + " DataArray '" + esc(a.attr("Name")) + "' claims " + std::to_string(count) +
                          " values, more than the " + std::to_string(file_bytes) + "-byte file can hold");
}

}  // namespace

void check_vtk_array_components(const VtkXmlElement& piece, const std::string& path) {
    for (const char* section : {"PointData", "CellData"})
        for (const VtkXmlElement& a : piece.child(section).children("DataArray")) (void)components_of(a, path);
}

namespace {

Vec3 mat(const std::array<double, 9>& d, double x, double y, double z) {
    return Vec3{d[0] * x + d[1] * y + d[2] * z, d[3] * x + d[4] * y + d[5] * z, d[6] * x + d[7] * y + d[8] * z};
}

}  // namespace

std::string describe_arrays(const std::vector<VtkArrayDesc>& arrays, bool scalars_only) {
    std::string s;
    for (const auto& a : arrays) {
        if (scalars_only && a.components != 1) continue;
        if (!s.empty()) s.append(", ");
        s.append("'").append(esc(a.name)).append("' (").append(a.cell ? "cell" : "point");
        if (a.components != 1) s.append(", ").append(std::to_string(a.components)).append(" components");
        s.append(")");
    }
    return s.empty() ? "none" : s;
}

VtkStructuredFile read_vtk_structured(const std::string& path, const PointSetOptions& o) {
    const auto bytes = read_file_bytes(path);
    if (bytes.empty()) throw FormatError(path + ": empty file");
    const VtkXmlDocument X(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
    const VtkXmlFile& F = X.file();
    VtkStructuredFile out;
    out.type = F.type;
    const bool image = F.type == "ImageData", curvilinear = F.type == "StructuredGrid", rectilinear = F.type == "RectilinearGrid";
    if (!image && !curvilinear && !rectilinear)
        throw FormatError(path + ": VTK XML type '" + esc(F.type) +
                          "' is not a structured grid (ImageData, StructuredGrid, RectilinearGrid)");
    const VtkXmlElement top = X.root().child(F.type.c_str());
    if (!top.found()) throw FormatError(path + ": missing <" + F.type + ">");
    std::array<double, 3> origin{0, 0, 0}, spacing{1, 1, 1};
    std::array<double, 9> dir{1, 0, 0, 0, 1, 0, 0, 0, 1};
    bool axis_aligned = true;
    if (image) {
        const auto org = vtk_xml_numbers<double>(top.attr("Origin", "0 0 0"), 3, path, "Origin");
        const auto sp = vtk_xml_numbers<double>(top.attr("Spacing", "1 1 1"), 3, path, "Spacing");
        for (int a = 0; a < 3; ++a) {
            if (!std::isfinite(org[a])) throw FormatError(path + ": non-finite Origin '" + esc(top.attr("Origin")) + "'");
            if (!std::isfinite(sp[a]) || sp[a] == 0)
                throw FormatError(path + ": bad Spacing '" + esc(top.attr("Spacing")) + "': zero or non-finite");
            origin[a] = org[a], spacing[a] = sp[a];
        }
        if (top.has_attr("Direction")) {
            const auto d = vtk_xml_numbers<double>(top.attr("Direction"), 9, path, "Direction");
            for (int i = 0; i < 9; ++i) {
                if (!std::isfinite(d[i])) throw FormatError(path + ": non-finite Direction");
                dir[i] = d[i];
                axis_aligned = axis_aligned && d[i] == (i % 4 == 0 ? 1.0 : 0.0);
            }
        }
    }
    const std::string file_name = std::filesystem::path(path).filename().string();
    std::string value_name;
    bool value_cell = false;
    int piece_no = 0;
    for (const VtkXmlElement& piece : top.children("Piece")) {
        const std::string where = "piece " + std::to_string(piece_no);
        if (piece.empty()) throw FormatError(path + ": " + where + " is empty");
        VtkStructuredPiece P;
        const VtkPieceExtent E = vtk_piece_extent(piece.attr("Extent", top.attr("WholeExtent")), path, piece_no);
        const std::array<std::int64_t, 6>& ext = E.extent;
        const std::array<std::int64_t, 3>& dims = E.dims;
        const std::array<std::int64_t, 3>& cells = E.cells;
        const std::uint64_t npoints = E.points, ncells = E.cell_count;
        P.extent = E.extent;
        // the scalar
        std::string pd_scalars, cd_scalars;
        std::vector<Cand> all = section_arrays(piece, "PointData", false, path, pd_scalars);
        for (auto& c : section_arrays(piece, "CellData", true, path, cd_scalars)) all.push_back(std::move(c));
        const Cand& chosen = choose(all, pd_scalars, cd_scalars, o, path + ": " + where);
        const bool cell = chosen.desc.cell;
        if (piece_no == 0) {
            for (const auto& c : all) out.arrays.push_back(c.desc);
            value_name = chosen.desc.name, value_cell = cell;
        } else if (chosen.desc.name != value_name || cell != value_cell) {
            throw FormatError(path + ": " + where + " has scalar '" + esc(chosen.desc.name) + "' (" + (cell ? "cell" : "point") +
                              " data), piece 0 has '" + esc(value_name) + "' (" + (value_cell ? "cell" : "point") + " data)");
        }
        const std::uint64_t count = cell ? ncells : npoints;
        check_fits(chosen.tag, count, F, bytes.size(), path, where);
        const std::vector<double> vals = vtk_xml_read_array(X, chosen.tag, count, path);
        std::vector<double> ghost;
        for (const auto& c : all)
            if (c.desc.name == "vtkGhostType" && c.desc.cell == cell && c.desc.components == 1) {
                check_fits(c.tag, count, F, bytes.size(), path, where);
                ghost = vtk_xml_read_array(X, c.tag, count, path);
            }
        // the point positions
        std::vector<double> xyz;
        std::array<std::vector<double>, 3> coord;
        if (curvilinear) {
            const VtkXmlElement pts = piece.child("Points");
            if (!pts.found() || pts.empty()) throw FormatError(path + ": " + where + " has no <Points>");
            const VtkXmlElement parr = pts.child("DataArray");
            if (!parr.found()) throw FormatError(path + ": " + where + ": <Points> without a DataArray");
            if (components_of(parr, path) != 3)
                throw FormatError(path + ": " + where + ": <Points> DataArray has " + esc(parr.attr("NumberOfComponents", "1")) +
                                  " components, expected 3");
            check_fits(parr, 3 * npoints, F, bytes.size(), path, where + " Points");
            xyz = vtk_xml_read_array(X, parr, 3 * npoints, path);
        } else if (rectilinear) {
            const VtkXmlElement cs = piece.child("Coordinates");
            if (!cs.found() || cs.empty()) throw FormatError(path + ": " + where + " has no <Coordinates>");
            const std::vector<VtkXmlElement> cas = cs.children("DataArray");
            for (int a = 0; a < 3; ++a) {
                if (static_cast<std::size_t>(a) >= cas.size())
                    throw FormatError(path + ": " + where + ": <Coordinates> needs 3 DataArrays, found " + std::to_string(a));
                const VtkXmlElement& ca = cas[static_cast<std::size_t>(a)];
                if (components_of(ca, path) != 1)
                    throw FormatError(path + ": " + where + ": <Coordinates> DataArray " + std::to_string(a) + " has several components");
                check_fits(ca, static_cast<std::uint64_t>(dims[a]), F, bytes.size(), path, where + " Coordinates");
                coord[a] = vtk_xml_read_array(X, ca, static_cast<std::uint64_t>(dims[a]), path);
            }
        } else {
            P.origin = origin, P.spacing = spacing, P.axis_aligned = axis_aligned;
        }
        auto point = [&](std::int64_t i, std::int64_t j, std::int64_t k) -> Vec3 {
            if (curvilinear) {
                const std::size_t n = static_cast<std::size_t>(3 * (i + dims[0] * (j + dims[1] * k)));
                return Vec3{xyz[n], xyz[n + 1], xyz[n + 2]};
            }
            if (rectilinear) return Vec3{coord[0][i], coord[1][j], coord[2][k]};
            const Vec3 d = mat(dir, static_cast<double>(ext[0] + i) * spacing[0], static_cast<double>(ext[2] + j) * spacing[1],
                               static_cast<double>(ext[4] + k) * spacing[2]);
            return Vec3{origin[0] + d.x, origin[1] + d.y, origin[2] + d.z};
        };
        StructuredBlock& b = P.block;
        b.name = file_name + (piece_no ? " piece " + std::to_string(piece_no) : "");
        b.cell_centred = cell;
        b.dims = cell ? cells : dims;
        b.node.resize(static_cast<std::size_t>(count));
        b.value = vals;
        b.valid.assign(static_cast<std::size_t>(count), 1);
        std::uint64_t invalid = 0;
        const unsigned hidden_bit = cell ? 0x08u : 0x02u;
        std::size_t n = 0;
        for (std::int64_t k = 0; k < b.dims[2]; ++k)
            for (std::int64_t j = 0; j < b.dims[1]; ++j)
                for (std::int64_t i = 0; i < b.dims[0]; ++i, ++n) {
                    Vec3 p{0, 0, 0};
                    if (!cell) {
                        p = point(i, j, k);
                    } else {
                        const std::int64_t i1 = dims[0] > 1 ? i + 1 : i, j1 = dims[1] > 1 ? j + 1 : j, k1 = dims[2] > 1 ? k + 1 : k;
                        for (const std::int64_t kk : {k, k1})
                            for (const std::int64_t jj : {j, j1})
                                for (const std::int64_t ii : {i, i1}) {
                                    const Vec3 c = point(ii, jj, kk);
                                    p.x += c.x, p.y += c.y, p.z += c.z;
                                }
                        p = Vec3{p.x / 8, p.y / 8, p.z / 8};
                    }
                    b.node[n] = p;
                    if (!ghost.empty() && ghost[n] >= 0 && ghost[n] < 256 && (static_cast<unsigned>(ghost[n]) & hidden_bit)) {
                        b.valid[n] = 0, ++P.blanked, ++invalid;
                    } else if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(vals[n])) {
                        if (o.strict)
                            throw FormatError(path + ": " + where + (cell ? " cell " : " point ") + std::to_string(n) +
                                              ": non-finite " + (std::isfinite(vals[n]) ? "coordinate" : "value") +
                                              " (NaN/Inf are refused in strict mode)");
                        b.valid[n] = 0, ++P.nonfinite, ++invalid;
                    }
                }
        if (invalid == count)
            throw FormatError(path + ": " + where + ": every " + (cell ? "cell" : "point") + " is blanked or non-finite");
        if (invalid == 0) b.valid.clear();
        out.pieces.push_back(std::move(P));
        if (++piece_no > 1000000) throw FormatError(path + ": more than a million pieces");
    }
    if (piece_no == 0) throw FormatError(path + ": no <Piece> in <" + F.type + ">");
    out.value_name = value_name;
    out.cell = value_cell;
    return out;
}

}  // namespace meshless
