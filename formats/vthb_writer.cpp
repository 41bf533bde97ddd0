#include "formats/vthb_writer.hpp"

#include <cstdio>
#include <filesystem>

#include "kernels/significant_text.hpp"
#include "formats/vtk_xml_output.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

std::string num(double v) { return significant_text(v, 17); }

std::string triple(const std::array<double, 3>& v) { return num(v[0]) + " " + num(v[1]) + " " + num(v[2]); }

}  // namespace

void write_vti_cells(const std::string& path, const std::array<std::int64_t, 3>& lo,
                     const std::array<std::int64_t, 3>& cells, const std::array<double, 3>& origin,
                     const std::array<double, 3>& spacing, const std::vector<double>& value,
                     const std::string& value_name) {
    if (cells[0] < 1 || cells[1] < 1 || cells[2] < 1 ||
        static_cast<std::int64_t>(value.size()) != cells[0] * cells[1] * cells[2])
        throw InvalidArgument(path + ": the cell values disagree with the box's extent");
    std::string ext;
    for (int a = 0; a < 3; ++a) {
        if (a) ext += ' ';
        ext += std::to_string(lo[a]);
        ext += ' ';
        ext += std::to_string(lo[a] + cells[a]);
    }
    const std::string name = vtk_xml_escape(value_name);
    std::string app;
    vtk_xml_append_raw(app, value.data(), value.size() * sizeof(double));
    const std::string x = vtk_xml_prologue("ImageData", "1.0") +
                          "  <ImageData WholeExtent=\"" + ext + "\" Origin=\"" + triple(origin) + "\" Spacing=\"" +
                          triple(spacing) + "\">\n"
                          "    <Piece Extent=\"" + ext + "\">\n"
                          "      <PointData>\n"
                          "      </PointData>\n"
                          "      <CellData Scalars=\"" + name + "\">\n"
                          "        <DataArray type=\"Float64\" Name=\"" + name + "\" format=\"appended\" offset=\"0\"/>\n"
                          "      </CellData>\n"
                          "    </Piece>\n"
                          "  </ImageData>\n";
    write_vtk_xml_appended(path, x, app);
}

std::vector<std::string> write_vthb(const std::string& path, const AmrHierarchy& h) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    if (p.extension() != ".vthb") throw InvalidArgument(path + ": an AMR output must end in .vthb");
    if (h.boxes.empty()) throw InvalidArgument(path + ": no box to write");
    for (const AmrBox& b : h.boxes)
        if (b.level < 0 || b.level >= h.levels)
            throw InvalidArgument(path + ": a box has level " + std::to_string(b.level) + " outside 0.." +
                                  std::to_string(h.levels - 1));
    const VtkPieceFolder pieces(path);
    std::vector<std::string> written;
    std::string x = vtk_xml_prologue("vtkOverlappingAMR", "1.1") +
                    "  <vtkOverlappingAMR origin=\"" + triple(h.origin) + "\" grid_description=\"XYZ\">\n";
    std::size_t n = 0;
    for (int level = 0; level < h.levels; ++level) {
        x += "    <Block level=\"" + std::to_string(level) + "\" spacing=\"" + triple(h.spacing(level)) + "\">\n";
        int index = 0;
        for (const AmrBox& b : h.boxes) {
            if (b.level != level) continue;
            const std::string rel = pieces.relative(n++, ".vti");
            const std::string piece = pieces.path_of(rel);
            write_vti_cells(piece, b.lo, b.cells(), h.origin, h.spacing(level), b.value, h.value_name);
            written.push_back(piece);
            x += "      <DataSet index=\"" + std::to_string(index++) + "\" amr_box=\"" + std::to_string(b.lo[0]) + " " +
                 std::to_string(b.hi[0]) + " " + std::to_string(b.lo[1]) + " " + std::to_string(b.hi[1]) + " " +
                 std::to_string(b.lo[2]) + " " + std::to_string(b.hi[2]) + "\" file=\"" + vtk_xml_escape(rel) + "\"/>\n";
        }
        x += "    </Block>\n";
    }
    x += "  </vtkOverlappingAMR>\n</VTKFile>\n";
    write_vtk_xml(path, x);
    return written;
}

}  // namespace meshless
