// The data and the field of the field commands (fit, probe, slice, resample, and isosurface, render
// and hierarchy over points or blocks), without a command line: one or several data files read as one point
// set (point sets, or every valid node of multiblock/AMR inputs), the field kind built when none is
// asked for, the field fitted under a thread count with its data errors naming the inputs, a fitted
// field (.mlf, formats/field_file.hpp) loaded and timed, the fitted field written with what its data
// was, and the reports of a build or a load that --stats prints; the recipes the front ends call
// (docs/architecture.md "Libraries").
// Units: world coordinates; seconds; memory in MiB in the reports.
// Throws FormatError for positions-only points and unusable data (make_field: an empty set, fewer
// than 4 distinct points; prefixed with the inputs' names), a damaged .mlf; InvalidArgument from
// make_field (parameters out of their domain); IoError from the readers and writers.
// Dissertation chapters 4-5 build the fields (sections 4.3, 5.5), chapter 7 looks at them.
#pragma once
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "formats/field_file.hpp"
#include "formats/point_set_options.hpp"
#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_coverage.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

/// The field built when none is asked for, by what the data is: chapter 5 projects the isosurface
/// of scattered points onto the MPU field (section 5.5); chapter 4 blends the RBF grid (section 4.3)
/// over multiblock nodes. Measured against rbf-grid for points
/// (`meshless-bench scattered --parts a --no-peers --sizes 10000,100000 [--field mpu]`, bench/MEASURED.md): on
/// the 18 analytic runs mpu's mean distance to the truth is 0.58-2.5x rbf-grid's (smaller in 11),
/// coverage >= 99 % in 11 runs against 10, and it is 1.1-3.6x faster end to end.
inline constexpr const char* kPointsFieldDefault = "mpu";
inline constexpr const char* kBlocksFieldDefault = "rbf-grid";

/// True when every path is a multiblock/AMR input (looks_like_multiblock) and there is one at least:
/// the data the block commands read, fitted with kBlocksFieldDefault.
bool all_multiblock(const std::vector<std::string>& paths);
/// The field built from these data files when none is asked for: kBlocksFieldDefault when
/// all_multiblock, else kPointsFieldDefault (what isosurface, fit, render, probe, slice and resample build).
std::string data_field_default(const std::vector<std::string>& paths);

/// A warning about an input: `subject` (a file name, to be escaped by whoever prints it) and what
/// is wrong with it, one line.
using InputWarning = std::function<void(const std::string& subject, const std::string& what)>;

/// Reads data files as one point set: when every path is a multiblock/AMR input
/// (looks_like_multiblock: .vts .vtm .vthb, PLOT3D) through read_multiblock and to_point_set (every
/// valid node, the set the block commands build their field from), else through read_point_set.
/// `command` names the command in the messages ("probe"); warn (may be empty) hears of a level of
/// detail asked beyond a cluster tree and, unless `warn_dropped` is false (a caller that reports
/// them itself), of the samples the readers dropped for a NaN/Inf position or value (--strict
/// refuses them instead). InvalidArgument, before any reading, for data the command cannot read
/// together ("-": the readers go by the file's name and contents; a volume among several files; a
/// level of detail asked of files that are no cluster tree); FormatError for positions-only points
/// (no value to fit, probe, render or cluster).
PointSet read_field_points(const std::vector<std::string>& paths, const PointSetOptions& options, const std::string& command,
                           const InputWarning& warn = {}, bool warn_dropped = true);

/// A field and where its data covers space (null coverage: values are the field's own, neither
/// masked nor kept within the data's range).
struct BuiltField {
    std::unique_ptr<Field> field;
    std::unique_ptr<PointCoverage> coverage;  ///< with the data values: support test and value band
    Extrapolate extrapolate = Extrapolate::nan;  ///< what the coverage does outside the data
    std::optional<FieldFileInfo> file;  ///< set when the field was loaded from a .mlf
    double load_seconds = 0;  ///< the load's time, when loaded
};

/// make_field(points, params, stats, progress, share) under at most `threads` workers (<= 0:
/// available_cpus()), its FormatError and IoError prefixed "INPUTS: " (`inputs`: the data files'
/// names, joined_names; the field's own messages name only the field).
std::unique_ptr<Field> fit_data_field(const PointSet& points, const FieldParams& params, const std::string& inputs, int threads,
                                      FieldBuildStats* stats, const FieldProgress& progress = {}, const FitShare* share = nullptr);

/// The .mlf at `path` (read_field_file), with `file` and `load_seconds` set; no coverage.
BuiltField load_built_field(const std::string& path);

/// Writes `field`, fitted to `points` with `params`, as a .mlf (write_field_file) recording the
/// points' identity and what the reader dropped; returns what was recorded.
FittedData write_fitted_field(const std::string& path, const Field& field, const FieldParams& params, const PointSet& points,
                              const FieldBuildStats& stats, int zstd_level);

/// Prints to `out` what building the field from `points` did ("COMMAND: mpu field from N points
/// (...)"): one line, and one more each for local fits that took another c and for fits whose
/// points lay in a plane or line.
void print_field_build_report(std::FILE* out, const std::string& command, const FieldParams& params, const PointSet& points,
                              const FieldBuildStats& st);
/// Prints to `out` the line of a fitted field written to `path` ("fit: read ... wrote PATH (N bytes,
/// identity ...)"; read, fit and write times in seconds).
void print_fit_report(std::FILE* out, const std::string& path, const FittedData& data, const FieldBuildStats& st, double read_seconds,
                      double write_seconds);
/// Prints to `out` the line of a field loaded from `path` ("COMMAND: mpu field loaded from PATH (...)").
void print_field_load_report(std::FILE* out, const std::string& command, const std::string& path, const FieldFileInfo& info,
                             double seconds);

}  // namespace meshless
