// Writers for scattered point sets with one scalar (the output of `meshless sample`, readable by
// formats/point_set_reader.hpp, ParaView and MeshLab).
//
// PLY: binary little endian, vertex properties `double x, y, z` (coordinates keep their digits
// at 1e6 offsets) and `double value` (named "value" whatever PointSet::value_name is; the name is
// recorded in a comment "value_name NAME"); no value property when has_values is false.
// CSV: header "x,y,z,value" (or "x,y,z"), one row per point, 17 significant digits (round-trips
// doubles exactly).
// Both go through AtomicFile (temporary + rename; "-" = stdout): nothing half-written on error.
// Throws IoError naming the path. Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "kernels/point_set.hpp"

namespace meshless {

void write_point_set_ply(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments = {});
void write_point_set_csv(const std::string& path, const PointSet& ps);
/// By extension: .ply -> PLY, .csv/.txt/.tsv or "-" -> CSV; anything else InvalidArgument.
void write_point_set(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments = {});

}  // namespace meshless
