// Oriented points from VTK XML PolyData (.vtp), as `meshless isosurface -o points.vtp` writes them
// (formats/vtp_writer.hpp) and ParaView saves them back: the splats of dissertation section 3.6.
//
// Every <Piece> in order; per point: the <Points> DataArray (3 components), the PointData array
// named by <PointData Normals=...> or called "Normals" (3 components, made unit length), "radius"
// (1 component, world units) and "value" (1 component; else the array named by <PointData
// Scalars=...>, else 0). Records with a non-finite position, normal, radius or value, a zero normal
// or a radius <= 0 are dropped and counted. The XML comments before <VTKFile> (the stream metadata
// the writer records as "key value" lines, `\xNN` escapes undone) are returned as they are.
// Payloads as formats/vtk_xml.hpp decodes them. Memory: the file and 32 bytes a point.
// Throws FormatError naming the file: another VTK type, a piece with polygons or strips (a mesh:
// write it as .ply for splat's mesh drawing), no Points, no normals or no radius array (with the
// arrays the file has), a wrong component count, sizes that disagree with NumberOfPoints, corrupt
// payloads; IoError when the file cannot be read. Thread-safety: reentrant.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/records.hpp"

namespace meshless {

struct OrientedPointsVtp {
    std::vector<PointRecord> points;
    std::vector<std::string> comments;  ///< the comments before <VTKFile>, in order
    std::uint64_t dropped = 0;          ///< records dropped as non-finite or degenerate
};

OrientedPointsVtp read_oriented_points_vtp(const std::string& path);

}  // namespace meshless
