#include "formats/points_vtu.hpp"

#include "formats/points_vtp.hpp"

namespace meshless {

PointSet read_points_vtu(const std::string& path, const PointSetOptions& options, std::vector<std::string>* notes) {
    return read_points_vtk_xml(path, "UnstructuredGrid", options, notes);
}

}  // namespace meshless
