#include "formats/file_names.hpp"
#include "formats/multiblock_reader.hpp"

#include <cctype>
#include <filesystem>

#include "formats/plot3d.hpp"
#include "kernels/amr_cover.hpp"
#include "formats/ply.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/vtk_multiblock.hpp"
#include "formats/vtk_structured.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

// A structured VTK XML file (.vts/.vti/.vtr): its pieces as blocks.
Multiblock read_vtk_file(const std::string& path, const PointSetOptions& o, MultiblockDetails* details) {
    VtkStructuredFile f = read_vtk_structured(path, o);
    Multiblock mb;
    mb.format = lower_extension(path).substr(1);
    mb.value_name = f.value_name;
    for (auto& p : f.pieces) {
        mb.blanked += p.blanked;
        mb.nonfinite += p.nonfinite;
        mb.blocks.push_back(std::move(p.block));
    }
    if (details) {
        details->description = "VTK XML " + f.type + ", " + std::to_string(mb.blocks.size()) + " piece(s)";
        details->arrays = f.arrays;
        details->cell = f.cell;
    }
    return mb;
}

// Anything else the point-set readers take (regular volumes: one block of voxels): blocks whose
// node count matches their dims are structured as they are; dropped samples would break the lattice.
Multiblock read_via_point_set(const std::string& path, const PointSetOptions& o) {
    PointSet ps = read_point_set(path, o);
    if (ps.dropped_blanked || ps.dropped_nonfinite)
        throw FormatError(path + ": " + std::to_string(ps.dropped_blanked + ps.dropped_nonfinite) +
                          " blanked or non-finite samples break the block lattice of this format");
    if (!ps.has_values) throw FormatError(path + ": positions only; a block input needs a scalar");
    Multiblock mb;
    const std::string e = lower_extension(path);
    mb.format = !e.empty() && looks_like_point_set(path) ? e.substr(1) : "volume";
    mb.value_name = ps.value_name;
    for (const auto& b : ps.blocks) {
        StructuredBlock sb;
        sb.name = b.name;
        sb.dims = b.dims;
        if (sb.dims[0] < 1 || sb.dims[1] < 1 || sb.dims[2] < 1 || sb.node_count() != static_cast<std::int64_t>(b.count))
            throw FormatError(path + ": block '" + ply_escape(b.name) + "' has " + std::to_string(b.count) +
                              " nodes, its dims imply " + std::to_string(sb.node_count()) + ": not a structured block");
        sb.node.assign(ps.pos.begin() + static_cast<std::ptrdiff_t>(b.first),
                       ps.pos.begin() + static_cast<std::ptrdiff_t>(b.first + b.count));
        sb.value.assign(ps.value.begin() + static_cast<std::ptrdiff_t>(b.first),
                        ps.value.begin() + static_cast<std::ptrdiff_t>(b.first + b.count));
        mb.blocks.push_back(std::move(sb));
    }
    return mb;
}

Multiblock read_one(const std::string& path, const PointSetOptions& o, MultiblockDetails* details) {
    const std::string e = lower_extension(path);
    if (e == ".vtm" || e == ".vthb") return read_vtk_collection(path, o, details);
    if (e == ".vts" || e == ".vti" || e == ".vtr") return read_vtk_file(path, o, details);
    std::vector<std::string> notes;
    Multiblock mb;
    if (e == ".p3d") mb = read_plot3d_meta_blocks(path, o, &notes);
    else if (e == ".xyz" || e == ".x" || e == ".g" || (e == ".bin" && looks_like_plot3d_xyz(path))) mb = read_plot3d_blocks(path, o, &notes);
    else return read_via_point_set(path, o);
    if (details) details->description = "PLOT3D, " + std::to_string(mb.blocks.size()) + " grid(s)";
    mb.notes = std::move(notes);
    return mb;
}

}  // namespace

bool looks_like_multiblock(const std::string& path) {
    const std::string e = lower_extension(path);
    if (e == ".vts" || e == ".vtr" || e == ".vtm" || e == ".vthb" || e == ".p3d" || e == ".xyz" || e == ".x" || e == ".g")
        return true;
    if (e == ".bin") return looks_like_plot3d_xyz(path);
    return false;
}

Multiblock read_multiblock(const std::vector<std::string>& paths, const PointSetOptions& options, MultiblockDetails& details) {
    if (paths.empty()) throw InvalidArgument("read_multiblock: no input files");
    Multiblock mb;
    std::string first_path;
    for (const auto& path : paths) {
        Multiblock one = read_one(path, options, mb.blocks.empty() ? &details : nullptr);
        if (mb.blocks.empty()) {
            mb.value_name = one.value_name;
            mb.format = one.format;
            first_path = path;
        } else {
            if (one.value_name != mb.value_name)
                throw FormatError(path + ": scalar '" + ply_escape(one.value_name) + "', but " + first_path + " has '" +
                                  ply_escape(mb.value_name) + "' (choose one with --value)");
            if (one.format != mb.format) mb.format = "mixed";
        }
        mb.blanked += one.blanked;
        mb.nonfinite += one.nonfinite;
        for (auto& n : one.notes) mb.notes.push_back(std::filesystem::path(path).filename().string() + ": " + n);
        for (auto& b : one.blocks) {
            if (paths.size() > 1 && b.name.find(std::filesystem::path(path).filename().string()) == std::string::npos)
                b.name = std::filesystem::path(path).filename().string() + " " + b.name;
            mb.blocks.push_back(std::move(b));
        }
    }
    // AMR: the finest data wins (kernels/amr_cover.hpp): coarse nodes under a finer box are not field data.
    mark_amr_covered(mb);
    return mb;
}

Multiblock read_multiblock(const std::vector<std::string>& paths, const PointSetOptions& options) {
    MultiblockDetails details;
    return read_multiblock(paths, options, details);
}

}  // namespace meshless
