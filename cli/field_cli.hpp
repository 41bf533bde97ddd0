// Shared pieces of the commands that use a meshless field built from scattered or multiblock
// points (fit, probe, slice, resample; isosurface/project over blocks): the field options
// (--field --binning --max-points --alpha --hardy-c --hardy-c-world --support --normalise-axes),
// reading the data (one or several files: point sets, or multiblock/AMR inputs as every valid node),
// building the field under --threads, or loading it from a fitted-field file: `--field FILE.mlf`
// (formats/field_file.hpp, written by `meshless fit`). Evaluation is a stage graph
// (stream/field_evaluate_stage.hpp). Throws UsageError for bad options, FormatError for a .mlf that
// is damaged or was fitted to other data than the command's (exit 2).
#pragma once
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "cli/args.hpp"
#include "formats/field_file.hpp"
#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_coverage.hpp"
#include "kernels/point_set.hpp"

namespace meshless::cli {

/// The field built when --field is not given, by what the data is: chapter 5 projects the isosurface
/// of scattered points onto the MPU field (section 5.5); chapter 4 blends the RBF grid (section 4.3)
/// over multiblock nodes. Measured against rbf-grid for points
/// (`meshless-bench scattered --parts a --no-peers --sizes 10000,100000 [--field mpu]`, bench/MEASURED.md): on
/// the 18 analytic runs mpu's mean distance to the truth is 0.58-2.5x rbf-grid's (smaller in 11),
/// coverage >= 99 % in 11 runs against 10, and it is 1.1-3.6x faster end to end.
inline constexpr const char* kPointsFieldDefault = "mpu";
inline constexpr const char* kBlocksFieldDefault = "rbf-grid";
/// The --field default as --help shows it for commands that take either kind of data.
inline constexpr const char* kDataFieldDefaultHelp = "mpu for point sets, rbf-grid for multiblock inputs";

/// with_coverage: also --max-gap and --extrapolate (commands that evaluate the field where the data
/// may not reach: probe, slice, resample). default_kind: the --field default shown in --help and
/// built when --field is absent (unless the command passes another to field_params/build_field).
void add_field_options(Args& a, bool with_coverage = true, const std::string& default_kind = kBlocksFieldDefault);
/// --field as given, else `default_kind` when not empty, else the default add_field_options declared.
std::string field_kind_arg(const Args& a, const std::string& default_kind = {});
/// The field parameters of the options (the kind: field_kind_arg(a, default_kind)); UsageError when
/// --field names a .mlf (see field_file_arg).
FieldParams field_params(const Args& a, const std::string& default_kind = {});
/// The .mlf named by --field, if it names one (ends in .mlf, or an existing file with the .mlf magic);
/// nullopt for a field kind (rbf-grid, mpu, global-rbf).
std::optional<std::string> field_file_arg(const Args& a);

/// True when every path is a multiblock/AMR input (looks_like_multiblock) and there is one at least:
/// the data the block commands read, fitted with kBlocksFieldDefault.
bool all_multiblock(const std::vector<std::string>& paths);
/// The field built from DATA files when --field is absent: kBlocksFieldDefault when all_multiblock,
/// else kPointsFieldDefault (what isosurface, fit, render, probe, slice and resample build).
std::string data_field_default(const std::vector<std::string>& paths);
/// Reads data files as one point set: when every path is a multiblock/AMR input
/// (looks_like_multiblock: .vts .vtm .vthb, PLOT3D) through read_multiblock and to_point_set (every
/// valid node, the set the block commands build their field from), else through read_point_set.
/// Throws FormatError for positions-only points (no value to fit, probe, render or cluster).
PointSet read_field_points(const std::vector<std::string>& paths, const Args& a);
/// read_field_points of the positional POINTS files.
/// make_field, its data errors (an empty set, fewer than 4 distinct points) naming the command's
/// inputs: the field's own messages name only the field.
std::unique_ptr<Field> make_input_field(const Args& a, const PointSet& points, const FieldParams& params,
                                        FieldBuildStats* stats, const FieldProgress& progress, const FitShare* share = nullptr);
PointSet read_points_arg(const Args& a);

/// A field and where its data covers space (--max-gap; null when --max-gap 0 or not declared: then
/// values are the field's own, neither masked nor kept within the data's range).
struct BuiltField {
    std::unique_ptr<Field> field;
    std::unique_ptr<PointCoverage> coverage;  ///< with the data values: support test and value band
    Extrapolate extrapolate = Extrapolate::nan;  ///< --extrapolate
    std::optional<FieldFileInfo> file;  ///< set when the field was loaded from a .mlf
};

/// Builds the field from `points` with --threads workers, or loads the .mlf named by --field after
/// checking that it was fitted to exactly `points` (FormatError otherwise; options that shape a fit,
/// like --binning, are then a UsageError). Prints a summary on stderr with --stats.
/// default_kind: as for field_params. share (optional): the mpu fits shared among MPI ranks
/// (kernels/field_params.hpp FitShare; a .mlf is loaded whole by every rank).
BuiltField build_field(const Args& a, const PointSet& points, const std::string& default_kind = {}, const FitShare* share = nullptr);
class ProgressMeter;
/// A FieldProgress that sets the meter's total from the build's report and counts the local fits.
FieldProgress field_progress(ProgressMeter& meter);

/// The --stats line of a field built from `points`.
void print_field_build_stats(const Args& a, const FieldParams& params, const PointSet& points, const FieldBuildStats& st);

/// For commands without the data: the .mlf named by --field, loaded (no coverage). UsageError when
/// --field names a field kind instead of a file.
BuiltField load_field_arg(const Args& a);

}  // namespace meshless::cli
