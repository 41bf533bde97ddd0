// Writers for scattered point sets with one scalar (the output of `meshless sample`, readable by
// formats/point_set_reader.hpp, ParaView and MeshLab).
//
// PLY: binary little endian, vertex properties `double x, y, z` (coordinates keep their digits
// at 1e6 offsets) and `double value` (named "value" whatever PointSet::value_name is; the name is
// recorded in a comment "value_name NAME"); no value property when has_values is false.
// CSV: header "x,y,z,value" (or "x,y,z"), one row per point, 17 significant digits (round-trips
// doubles exactly).
// VTP: VTK XML PolyData of float32 points, one vertex cell each, and the `value` array (ParaView
// opens it at once; formats/vtp_writer.hpp with oriented = false: no normals, no radii).
// All go through AtomicFile (temporary + rename; "-" = stdout as CSV): nothing half-written on error.
// Throws IoError naming the path. Thread-safety: reentrant.
// PointSetWriter writes the same files chunk by chunk (memory bounded whatever the count: the PLY
// declares the count first, which the appends must reach exactly; VTP spools its arrays to disk).
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/point_set.hpp"

namespace meshless {

/// A point set with values (or without: has_values false) written by extension as write_point_set
/// does, one chunk at a time. PLY: `count` is the number of points the appends will give; commit()
/// throws std::logic_error when they gave another number. CSV and VTP take any number.
enum class PointSetFormat { ply, csv, vtp };

/// By extension: .ply, .csv or "-", .vtp; anything else InvalidArgument (as write_point_set).
PointSetFormat point_set_output_format(const std::string& path);

class PointSetWriter {
public:
    /// The format by the name's extension (point_set_output_format).
    PointSetWriter(const std::string& path, std::uint64_t count, bool has_values, const std::string& value_name,
                   const std::vector<std::string>& comments = {});
    /// This format whatever the name.
    PointSetWriter(PointSetFormat format, const std::string& path, std::uint64_t count, bool has_values,
                   const std::string& value_name, const std::vector<std::string>& comments = {});
    ~PointSetWriter();
    PointSetWriter(const PointSetWriter&) = delete;
    PointSetWriter& operator=(const PointSetWriter&) = delete;
    /// value: one per position (ignored without values).
    void append(std::span<const Vec3> pos, std::span<const double> value);
    /// Renames into place; no appends after.
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

void write_point_set_ply(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments = {});
void write_point_set_csv(const std::string& path, const PointSet& ps);
/// Whether write_point_set takes this output name: .ply, .csv, .vtp (any case) or "-".
bool point_set_output_name(const std::string& path);
/// By extension: .ply -> PLY, .csv or "-" -> CSV, .vtp -> VTP; anything else InvalidArgument
/// ("-o 'NAME': this output is a point set with values, written to a .ply, .csv or .vtp file ...").
void write_point_set(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments = {});

}  // namespace meshless
