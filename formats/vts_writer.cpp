#include "formats/vts_writer.hpp"

#include <cstdint>
#include <cstring>
#include <vector>

#include "kernels/errors.hpp"

namespace meshless {

void write_vts(const std::string& path, const StructuredBlock& b, const std::string& value_name) {
    const std::int64_t n = b.node_count();
    if (b.dims[0] < 1 || b.dims[1] < 1 || b.dims[2] < 1 || static_cast<std::int64_t>(b.node.size()) != n ||
        static_cast<std::int64_t>(b.value.size()) != n || (!b.valid.empty() && static_cast<std::int64_t>(b.valid.size()) != n))
        throw InvalidArgument(path + ": block '" + vtk_xml_escape(b.name) + "' has arrays that disagree with its dims");
    const std::string ext = "0 " + std::to_string(b.dims[0] - 1) + " 0 " + std::to_string(b.dims[1] - 1) + " 0 " +
                            std::to_string(b.dims[2] - 1);
    const std::string name = vtk_xml_escape(value_name);
    std::vector<float> values(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<float>(b.value[i]);
    std::vector<double> pts(3 * static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < b.node.size(); ++i) {
        pts[3 * i] = b.node[i].x, pts[3 * i + 1] = b.node[i].y, pts[3 * i + 2] = b.node[i].z;
    }
    std::string app;
    const std::size_t off_values = app.size();
    vtk_xml_append_raw(app, values.data(), values.size() * sizeof(float));
    std::size_t off_ghost = 0;
    if (!b.valid.empty()) {
        std::vector<std::uint8_t> ghost(b.valid.size());
        for (std::size_t i = 0; i < ghost.size(); ++i) ghost[i] = b.valid[i] ? 0 : 1;
        off_ghost = app.size();
        vtk_xml_append_raw(app, ghost.data(), ghost.size());
    }
    const std::size_t off_points = app.size();
    vtk_xml_append_raw(app, pts.data(), pts.size() * sizeof(double));

    std::string x = vtk_xml_prologue("StructuredGrid", "1.0") +
                    "  <StructuredGrid WholeExtent=\"" + ext + "\">\n"
                    "    <Piece Extent=\"" + ext + "\">\n"
                    "      <PointData Scalars=\"" + name + "\">\n"
                    "        <DataArray type=\"Float32\" Name=\"" + name + "\" format=\"appended\" offset=\"" +
                    std::to_string(off_values) + "\"/>\n";
    if (!b.valid.empty())
        x += "        <DataArray type=\"UInt8\" Name=\"vtkGhostType\" format=\"appended\" offset=\"" +
             std::to_string(off_ghost) + "\"/>\n";
    x += "      </PointData>\n"
         "      <CellData>\n"
         "      </CellData>\n"
         "      <Points>\n"
         "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" +
         std::to_string(off_points) + "\"/>\n"
         "      </Points>\n"
         "    </Piece>\n"
         "  </StructuredGrid>\n";
    write_vtk_xml_appended(path, x, app);
}

}  // namespace meshless
