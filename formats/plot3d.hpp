// PLOT3D multiblock curvilinear grids read as point sets with values (dissertation chapter 5:
// overlapping grids as scattered data; connectivity dropped, blocks keep their dims).
//
// xyz files: single or multi-grid; C layout or Fortran sequential records (markers checked);
// little or big endian; float32 or float64; with or without IBLANK (int32 per point; points with
// IBLANK 0 are dropped and counted in dropped_blanked); or ASCII. The layout is detected: the one
// combination whose header is plausible and whose size equals the file size. A forced byte order
// (options.byte_order) under which no layout fits while the other order fits is refused with a
// message saying so (dims that only make sense byte-swapped).
// Values: a q file (options.q_file, else the sibling named like the xyz file with "xyz" -> "q",
// e.g. combxyz.bin -> combq.bin, multi-bin.xyz -> multi-bin.q) with 4 header reals (fsmach, alpha,
// re, time) and 5 fields per grid; options.q_component 0..4 (rho, rho*u, rho*v, rho*w, rho*E) or 5
// (speed |rho*u|/rho), or by value_name (density|rho, rhou, rhov, rhow, energy|rhoe, speed).
// Or a function file (options.function_file, header i j k nvars per grid; variable value_index,
// default 0). q/function files must use the xyz file's byte order, precision and record layout;
// their grid count and dims must equal the xyz file's (FormatError "... disagree" otherwise).
// Without q/function file: positions only (has_values = false).
// Trailing bytes after what the headers account for are refused unless options.allow_trailing
// (bluntfinq.bin has 484): then a note says how many were ignored.
// .p3d files (VTK's JSON meta format) name xyz/q/function files (relative to the .p3d) and may
// give "byte-order"; with several "filenames" entries (time steps) the first is read (a note).
// Structured read (read_plot3d_blocks, dissertation chapter 4): the same parse (one layout
// detection), each grid a StructuredBlock with every node kept in its lattice: IBLANK 0 nodes get
// valid = 0 (counted in Multiblock::blanked), NaN/Inf coordinates or values valid = 0 (counted in
// Multiblock::nonfinite; options.strict: FormatError "PATH: grid G point I: non-finite ...").
// A grid whose every node is invalid, or an xyz file without q/function values: FormatError.
// Units: the file's. Throws FormatError/IoError, one line starting with the offending path.
// Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

PointSet read_plot3d(const std::string& xyz_path, const PointSetOptions& options,
                     std::vector<std::string>* notes = nullptr);
/// A .p3d JSON meta file.
PointSet read_plot3d_meta(const std::string& p3d_path, const PointSetOptions& options,
                          std::vector<std::string>* notes = nullptr);
/// The grids as structured blocks (format "plot3d"), values as read_plot3d chooses them.
Multiblock read_plot3d_blocks(const std::string& xyz_path, const PointSetOptions& options,
                              std::vector<std::string>* notes = nullptr);
/// A .p3d meta file read as structured blocks.
Multiblock read_plot3d_meta_blocks(const std::string& p3d_path, const PointSetOptions& options,
                                   std::vector<std::string>* notes = nullptr);
/// True when the file's first bytes parse as a plausible PLOT3D xyz header (any supported layout).
bool looks_like_plot3d_xyz(const std::string& path);
/// The sibling q file of an xyz file ("" when there is none on disk).
std::string plot3d_sibling_q(const std::string& xyz_path);

}  // namespace meshless
