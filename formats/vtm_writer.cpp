#include "formats/vtm_writer.hpp"

#include <filesystem>

#include "formats/vtk_xml_output.hpp"
#include "formats/vts_writer.hpp"
#include "kernels/errors.hpp"

namespace meshless {

std::vector<std::string> write_vtm(const std::string& path, const Multiblock& mb) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    if (p.extension() != ".vtm") throw InvalidArgument(path + ": a multiblock output must end in .vtm");
    if (mb.blocks.empty()) throw InvalidArgument(path + ": no block to write");
    const VtkPieceFolder pieces(path);
    std::vector<std::string> written;
    std::string x = vtk_xml_prologue("vtkMultiBlockDataSet", "1.0") + "  <vtkMultiBlockDataSet>\n";
    for (std::size_t b = 0; b < mb.blocks.size(); ++b) {
        const std::string rel = pieces.relative(b, ".vts");
        const std::string piece = pieces.path_of(rel);
        write_vts(piece, mb.blocks[b], mb.value_name.empty() ? "scalars" : mb.value_name);
        written.push_back(piece);
        x += "    <DataSet index=\"" + std::to_string(b) + "\" name=\"" + vtk_xml_escape(mb.blocks[b].name) +
             "\" file=\"" + vtk_xml_escape(rel) + "\"/>\n";
    }
    x += "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
    write_vtk_xml(path, x);
    return written;
}

}  // namespace meshless
