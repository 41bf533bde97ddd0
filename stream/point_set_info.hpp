// The descriptions of point data for stream/file_info.hpp: PLY point sets and meshes (the header
// and the whole body read through, the vertices summarised), point sets of any format
// formats/point_set_reader.hpp takes, and VTK multiblock/AMR collections (.vtm, .vthb,
// formats/multiblock_reader.hpp), each as lines on `out`.
// Throws what the readers throw (FormatError, IoError). Thread-safety: reentrant (distinct `out`).
#pragma once
#include <cstdio>
#include <string>

#include "formats/point_set_options.hpp"

namespace meshless {

/// Vertex count, bounds, the range of every other vertex property, non-finite values, the other
/// elements counted, then the header. A mesh's faces are checked as `meshless splat` reads them.
void describe_ply(const std::string& path, std::FILE* out);
/// Format, reader notes, points, blocks and their dims (16 listed), value name and range, bounds,
/// dropped samples.
void describe_point_set(const std::string& path, const PointSetOptions& options, std::FILE* out);
/// Every piece opened and checked against the hierarchy: levels, boxes, refinement, arrays, the
/// chosen array's range, nodes, bounds, the pieces read, blocks and their dims (16 listed).
void describe_multiblock(const std::string& path, const PointSetOptions& options, std::FILE* out);

}  // namespace meshless
