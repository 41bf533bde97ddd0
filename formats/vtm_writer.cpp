#include "formats/vtm_writer.hpp"

#include <filesystem>

#include "formats/atomic_file.hpp"
#include "formats/vts_writer.hpp"
#include "kernels/errors.hpp"

namespace meshless {

std::vector<std::string> write_vtm(const std::string& path, const Multiblock& mb) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    if (p.extension() != ".vtm") throw InvalidArgument(path + ": a multiblock output must end in .vtm");
    if (mb.blocks.empty()) throw InvalidArgument(path + ": no block to write");
    const std::string stem = p.stem().string();
    const fs::path dir = p.parent_path() / stem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir, ec)) throw IoError(dir.string() + ": cannot create the folder for the pieces");
    std::vector<std::string> written;
    std::string x = "<?xml version=\"1.0\"?>\n"
                    "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
                    "  <vtkMultiBlockDataSet>\n";
    for (std::size_t b = 0; b < mb.blocks.size(); ++b) {
        const std::string rel = stem + "/" + stem + "_" + std::to_string(b) + ".vts";
        const fs::path piece = p.parent_path() / rel;
        write_vts(piece.string(), mb.blocks[b], mb.value_name.empty() ? "scalars" : mb.value_name);
        written.push_back(piece.string());
        x += "    <DataSet index=\"" + std::to_string(b) + "\" name=\"" + vtk_xml_escape(mb.blocks[b].name) +
             "\" file=\"" + vtk_xml_escape(rel) + "\"/>\n";
    }
    x += "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
    AtomicFile f(path);
    f.write(x);
    f.commit();
    return written;
}

}  // namespace meshless
