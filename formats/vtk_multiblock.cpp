#include "formats/file_names.hpp"
#include "formats/vtk_multiblock.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "formats/binary_file.hpp"
#include "formats/ply.hpp"
#include "formats/text_header.hpp"
#include "formats/vtk_xml.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

std::string esc(const std::string& s, std::size_t max = 96) { return ply_escape(s, max); }

bool is_amr_type(const std::string& t) {
    return t == "vtkOverlappingAMR" || t == "vtkHierarchicalBoxDataSet" || t == "vtkUniformGridAMR";
}

// One piece of the collection, with its errors re-thrown naming the collection and the piece. A
// piece listed twice is refused (it would multiply what one file's bytes can make the reader
// allocate, and no writer lists a piece twice).
VtkStructuredFile read_piece(const std::string& coll, const std::string& rel, const std::string& label,
                             const PointSetOptions& o, bool amr, std::set<std::string>& seen) {
    const std::string tag = coll + ": piece '" + esc(rel, 200) + "' (" + label + ")";
    const std::string e = lower_extension(rel);
    if (amr ? e != ".vti" : (e != ".vts" && e != ".vti" && e != ".vtr"))
        throw FormatError(tag + ": unsupported piece type '" + esc(e) + "' (" + (amr ? ".vti" : ".vts, .vti, .vtr") + ")");
    const std::string piece_path = resolve_relative(coll, rel);
    if (!seen.insert(std::filesystem::path(piece_path).lexically_normal().string()).second)
        throw FormatError(tag + ": the piece is listed twice");
    try {
        return read_vtk_structured(piece_path, o);
    } catch (const IoError& x) {
        throw FormatError(tag + ": " + esc(x.what(), 400));
    } catch (const FormatError& x) {
        throw FormatError(tag + ": " + esc(x.what(), 400));
    }
}

struct Chosen {
    std::string name, piece;
    bool cell = false;
    bool set = false;
};

void agree(Chosen& c, const VtkStructuredFile& f, const std::string& coll, const std::string& piece, bool amr) {
    if (!c.set) {
        c = Chosen{f.value_name, piece, f.cell, true};
        return;
    }
    if (f.value_name != c.name)
        throw FormatError(coll + ": piece '" + esc(piece) + "' has scalar '" + esc(f.value_name) + "', piece '" + esc(c.piece) +
                          "' has '" + esc(c.name) + "' (choose one with --value)");
    if (amr && f.cell != c.cell)
        throw FormatError(coll + ": mixed centring: array '" + esc(c.name) + "' is " + (c.cell ? "cell" : "point") +
                          " data in piece '" + esc(c.piece) + "' but " + (f.cell ? "cell" : "point") + " data in piece '" +
                          esc(piece) + "'");
}

void add_blocks(Multiblock& mb, VtkStructuredFile& f, const std::string& name, int level) {
    for (std::size_t p = 0; p < f.pieces.size(); ++p) {
        auto& P = f.pieces[p];
        P.block.name = f.pieces.size() > 1 ? name + " piece " + std::to_string(p) : name;
        P.block.level = level;
        mb.blanked += P.blanked;
        mb.nonfinite += P.nonfinite;
        mb.blocks.push_back(std::move(P.block));
    }
}

Multiblock read_plain(const std::string& path, const VtkXmlElement& top, const PointSetOptions& o,
                      MultiblockDetails* details) {
    Multiblock mb;
    mb.format = "vtm";
    Chosen chosen;
    std::set<std::string> seen;
    std::size_t empty = 0, count = 0;
    for (const VtkXmlElement& ds : top.descendants("DataSet")) {  // in nested <Block>s too
        const std::string file = ds.attr("file");
        if (file.empty()) {
            ++empty;
            continue;
        }
        const std::string label = "DataSet " + std::to_string(count);
        VtkStructuredFile f = read_piece(path, file, label, o, false, seen);
        if (details) details->files.push_back(resolve_relative(path, file));
        agree(chosen, f, path, file, false);
        if (details && details->arrays.empty()) {
            details->arrays = f.arrays;
            details->cell = f.cell;
        }
        const std::string name = esc(ds.attr("name", std::filesystem::path(file).filename().string()), 200);
        add_blocks(mb, f, name, 0);
        if (++count > 100000) throw FormatError(path + ": more than 100000 pieces");
    }
    if (mb.blocks.empty()) throw FormatError(path + ": no DataSet with a file in the multiblock");
    if (empty) mb.notes.push_back(std::to_string(empty) + " DataSet entries without a file (empty blocks) skipped");
    mb.value_name = chosen.name;
    if (details) details->description = "VTK multiblock (vtkMultiBlockDataSet), " + std::to_string(count) + " pieces";
    return mb;
}

struct Box {
    int level = 0;
    std::string index, file;
    std::array<std::int64_t, 6> box{};
};

double rel_diff(double a, double b) { return std::fabs(a - b) / std::max({std::fabs(a), std::fabs(b), 1e-300}); }

Multiblock read_amr(const std::string& path, const VtkXmlElement& file_tag, const VtkXmlElement& top,
                    const PointSetOptions& o, MultiblockDetails* details) {
    constexpr int kMaxLevels = 64;
    std::vector<Box> boxes;
    std::map<int, std::array<double, 3>> spacing;  // declared (1.x) or from the first piece (0.1)
    std::map<int, int> declared_ratio;             // 0.1: RefinementRatio
    std::optional<std::array<double, 3>> origin;
    std::size_t empty = 0;
    auto level_of = [&](const std::string& t, const char* what) {
        const auto v = vtk_xml_numbers<std::int64_t>(t, 1, path, what);
        if (v[0] < 0 || v[0] >= kMaxLevels) throw FormatError(path + ": " + what + " '" + esc(t) + "' out of 0.." + std::to_string(kMaxLevels - 1));
        return static_cast<int>(v[0]);
    };
    auto add_box = [&](const VtkXmlElement& ds, int level, const std::string& index) {
        const std::string file = ds.attr("file");
        if (file.empty()) {
            ++empty;
            return;
        }
        Box b;
        b.level = level, b.index = index, b.file = file;
        const std::string where = "amr_box of level " + std::to_string(level) + " box " + esc(index);
        const auto v = vtk_xml_numbers<std::int64_t>(ds.attr("amr_box"), 6, path, where);
        for (int a = 0; a < 3; ++a)
            if (v[2 * a + 1] < v[2 * a] || v[2 * a] < -(std::int64_t(1) << 40) || v[2 * a + 1] > (std::int64_t(1) << 40))
                throw FormatError(path + ": bad " + where + " '" + esc(ds.attr("amr_box")) + "'");
        std::copy(v.begin(), v.end(), b.box.begin());
        boxes.push_back(std::move(b));
        if (boxes.size() > 1000000) throw FormatError(path + ": more than a million AMR boxes");
    };
    const std::vector<VtkXmlElement> blocks = top.descendants("Block");
    const bool v1 = !blocks.empty();
    if (v1) {
        if (top.has_attr("origin")) {
            const auto org = vtk_xml_numbers<double>(top.attr("origin"), 3, path, "origin");
            for (double x : org)
                if (!std::isfinite(x)) throw FormatError(path + ": non-finite origin '" + esc(top.attr("origin")) + "'");
            origin = std::array<double, 3>{org[0], org[1], org[2]};
        }
        for (const VtkXmlElement& blk : blocks) {
            const int level = level_of(blk.attr("level"), "Block level");
            if (spacing.count(level)) throw FormatError(path + ": level " + std::to_string(level) + " appears twice");
            const auto sp = vtk_xml_numbers<double>(blk.attr("spacing"), 3, path, "spacing of level " + std::to_string(level));
            for (double s : sp)
                if (!std::isfinite(s) || s <= 0)
                    throw FormatError(path + ": bad spacing of level " + std::to_string(level) + " '" + esc(blk.attr("spacing")) +
                                      "': zero, negative or non-finite");
            spacing[level] = {sp[0], sp[1], sp[2]};
            for (const VtkXmlElement& ds : blk.children("DataSet"))
                add_box(ds, level, ds.attr("index", std::to_string(boxes.size())));
        }
    } else {
        for (const VtkXmlElement& rr : top.descendants("RefinementRatio")) {
            const int level = level_of(rr.attr("level"), "RefinementRatio level");
            const auto r = vtk_xml_numbers<std::int64_t>(rr.attr("refinement"), 1, path, "refinement");
            if (r[0] < 1 || r[0] > 1024) throw FormatError(path + ": bad refinement '" + esc(rr.attr("refinement")) + "'");
            declared_ratio[level] = static_cast<int>(r[0]);
        }
        for (const VtkXmlElement& ds : top.descendants("DataSet"))
            add_box(ds, level_of(ds.attr("group", "0"), "DataSet group"), ds.attr("dataset", std::to_string(boxes.size())));
    }
    if (boxes.empty()) throw FormatError(path + ": no AMR box with a file");

    Multiblock mb;
    mb.format = v1 ? "vthb" : "vtm-amr";
    Chosen chosen;
    std::set<std::string> seen;
    std::map<int, std::size_t> per_level;
    for (const Box& b : boxes) {
        const std::string label = "level " + std::to_string(b.level) + " box " + esc(b.index);
        VtkStructuredFile f = read_piece(path, b.file, label, o, true, seen);
        if (details) details->files.push_back(resolve_relative(path, b.file));
        const std::string tag = path + ": piece '" + esc(b.file, 200) + "' (" + label + ")";
        if (f.type != "ImageData") throw FormatError(tag + ": an AMR piece must be ImageData, not " + esc(f.type));
        if (f.pieces.size() != 1) throw FormatError(tag + ": " + std::to_string(f.pieces.size()) + " <Piece> elements, an AMR box has one");
        agree(chosen, f, path, b.file, true);
        const VtkStructuredPiece& P = f.pieces.front();
        if (!P.axis_aligned) throw FormatError(tag + ": a non-identity Direction in an AMR piece");
        const auto it = spacing.try_emplace(b.level, P.spacing);
        const std::array<double, 3>& h = it.first->second;
        std::array<double, 3> lo{};
        for (int a = 0; a < 3; ++a) {
            const std::int64_t npts = P.extent[2 * a + 1] - P.extent[2 * a] + 1;
            const std::int64_t cells = npts > 1 ? npts - 1 : 1;
            const std::int64_t want = b.box[2 * a + 1] - b.box[2 * a] + 1;
            if (cells != want)
                throw FormatError(tag + ": its extent has " + std::to_string(cells) + " cells along " + "xyz"[a] +
                                  ", its amr_box '" + std::to_string(b.box[0]) + " " + std::to_string(b.box[1]) + " " +
                                  std::to_string(b.box[2]) + " " + std::to_string(b.box[3]) + " " + std::to_string(b.box[4]) +
                                  " " + std::to_string(b.box[5]) + "' has " + std::to_string(want));
            if (!(P.spacing[a] > 0))
                throw FormatError(tag + ": Spacing " + number_text(P.spacing[a]) + " along " + "xyz"[a] + " is not positive");
            if (rel_diff(P.spacing[a], h[a]) > 1e-5)
                throw FormatError(tag + ": Spacing " + number_text(P.spacing[a]) + " along " + "xyz"[a] +
                                  " contradicts the level's spacing " + number_text(h[a]));
            lo[a] = P.origin[a] + static_cast<double>(P.extent[2 * a]) * P.spacing[a] - static_cast<double>(b.box[2 * a]) * h[a];
        }
        if (!origin) origin = lo;
        for (int a = 0; a < 3; ++a)
            if (std::fabs(lo[a] - (*origin)[a]) > 1e-3 * h[a])
                throw FormatError(tag + ": its origin puts amr_box index " + std::to_string(b.box[2 * a]) + " at " +
                                  number_text(P.origin[a] + static_cast<double>(P.extent[2 * a]) * P.spacing[a]) + " along " +
                                  "xyz"[a] + ", the hierarchy puts it at " +
                                  number_text((*origin)[a] + static_cast<double>(b.box[2 * a]) * h[a]));
        if (details && details->arrays.empty()) {
            details->arrays = f.arrays;
            details->cell = f.cell;
        }
        ++per_level[b.level];
        add_blocks(mb, f, label, b.level);
    }
    // refinement ratios between consecutive levels, checked against the declared ones (0.1)
    std::vector<MultiblockLevel> levels;
    for (const auto& [level, n] : per_level) {
        MultiblockLevel L;
        L.level = level, L.boxes = n, L.spacing = spacing.at(level);
        if (const auto prev = spacing.find(level - 1); prev != spacing.end() && per_level.count(level - 1)) {
            const double r = prev->second[0] / L.spacing[0];
            L.refinement = static_cast<int>(std::lround(r));
            for (int a = 0; a < 3; ++a)
                if (rel_diff(prev->second[a] / L.spacing[a], L.refinement) > 1e-3 || L.refinement < 1)
                    throw FormatError(path + ": level " + std::to_string(level) + " spacing " + std::to_string(L.spacing[a]) +
                                      " is not an integer refinement of level " + std::to_string(level - 1) + "'s " +
                                      std::to_string(prev->second[a]));
            if (const auto d = declared_ratio.find(level - 1); d != declared_ratio.end() && d->second != L.refinement)
                throw FormatError(path + ": RefinementRatio of level " + std::to_string(level - 1) + " is " +
                                  std::to_string(d->second) + " but the pieces' spacings give " + std::to_string(L.refinement));
        }
        levels.push_back(L);
    }
    if (empty) mb.notes.push_back(std::to_string(empty) + " AMR boxes without a file skipped");
    mb.value_name = chosen.name;
    if (details) {
        details->description = std::string("VTK AMR, ") + (v1 ? "" : "older ") + esc(file_tag.attr("type")) + " XML " +
                               esc(file_tag.attr("version", "?")) + ", " + std::to_string(boxes.size()) + " boxes in " +
                               std::to_string(levels.size()) + " levels";
        details->levels = levels;
        details->origin = origin;
    }
    return mb;
}

}  // namespace

bool is_vtk_amr(const std::string& path) {
    try {
        const std::string head = read_file_prefix(path, 4096);
        // the <VTKFile> start tag (a prefix: the rest of the document is not needed)
        const std::size_t at = head.find("<VTKFile"), gt = head.find('>', at);
        if (at == std::string::npos || gt == std::string::npos) return false;
        const std::string tag = head.substr(at, gt - at) + (head[gt - 1] == '/' ? ">" : "/>");
        const VtkXmlDocument X(tag, path);
        const VtkXmlElement t = X.root();
        return t.found() && is_amr_type(t.attr("type"));
    } catch (const std::exception&) {
        return false;
    }
}

Multiblock read_vtk_collection(const std::string& path, const PointSetOptions& o, MultiblockDetails* details) {
    const auto bytes = read_file_bytes(path);
    if (bytes.empty()) throw FormatError(path + ": empty file");
    const VtkXmlDocument X(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
    const VtkXmlFile& F = X.file();
    const VtkXmlElement file_tag = X.root();
    const bool amr = is_amr_type(F.type);
    if (!amr && F.type != "vtkMultiBlockDataSet")
        throw FormatError(path + ": VTK XML type '" + esc(F.type) +
                          "' is not a collection (vtkMultiBlockDataSet, vtkOverlappingAMR, vtkHierarchicalBoxDataSet)");
    // the element under <VTKFile>: named after the type (older files: vtkHierarchicalBoxDataSet for AMR)
    VtkXmlElement top = file_tag.child(F.type.c_str());
    if (!top.found() && amr)
        for (const char* n : {"vtkOverlappingAMR", "vtkHierarchicalBoxDataSet", "vtkUniformGridAMR"})
            if (!top.found()) top = file_tag.child(n);
    if (!top.found()) throw FormatError(path + ": missing <" + esc(F.type) + "> element");
    return amr ? read_amr(path, file_tag, top, o, details) : read_plain(path, top, o, details);
}

}  // namespace meshless
