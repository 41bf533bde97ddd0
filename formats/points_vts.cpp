#include "formats/points_vts.hpp"

#include "formats/points_vtp.hpp"

namespace meshless {

PointSet read_points_vts(const std::string& path, const PointSetOptions& options, std::vector<std::string>* notes) {
    return read_points_vtk_xml(path, "StructuredGrid", options, notes);
}

}  // namespace meshless
