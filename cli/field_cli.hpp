// The command-line side of the field commands (fit, probe, slice, resample, and isosurface, project,
// render and hierarchy over points or blocks): the field options (--field --binning --max-points --alpha
// --hardy-c --hardy-c-world --support --normalise-axes --max-gap --extrapolate --stats) declared and
// turned into FieldParams, the data files read as one point set, and the field built under --threads
// with a progress line or loaded from `--field FILE.mlf`, through stream/field_data.hpp. Throws
// UsageError for bad options, FormatError for a .mlf that is damaged or was fitted to other data than
// the command's (exit 2).
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_set.hpp"
#include "stream/field_data.hpp"
#include "stream/store_field_queries.hpp"

namespace meshless::cli {

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

/// stream/field_data.hpp read_field_points with the point-set options; warnings go to stderr (the
/// samples dropped as NaN/Inf among them unless `warn_dropped` is false: a command that reports them
/// itself).
PointSet read_field_points(const std::vector<std::string>& paths, const Args& a, bool warn_dropped = true);
/// read_field_points of the positional POINTS files.
PointSet read_points_arg(const Args& a, bool warn_dropped = true);

/// fit_data_field (stream/field_data.hpp) under --threads, with a progress line of the local fits
/// on commands that declare --quiet; first a UsageError when the mpu octree --alpha implies would not
/// fit in memory.
std::unique_ptr<Field> fit_input_field(const Args& a, const PointSet& points, const FieldParams& params, FieldBuildStats& stats,
                                       const FitShare* share = nullptr);

/// Builds the field from `points` (fit_input_field), or loads the .mlf named by --field after
/// checking that it was fitted to exactly `points` (FormatError otherwise; options that shape a fit,
/// like --binning, are then a UsageError); with --max-gap declared, the coverage (null for --max-gap
/// 0) and --extrapolate. Prints a summary on stderr with --stats.
/// default_kind: as for field_params. share (optional): the mpu fits shared among MPI ranks
/// (kernels/field_params.hpp FitShare; a .mlf is loaded whole by every rank).
BuiltField build_field(const Args& a, const PointSet& points, const std::string& default_kind = {}, const FitShare* share = nullptr);

/// --max-gap and --extrapolate (commands with add_field_options(a, true)): the support test's factor
/// (0: none) and what a position outside the data gets. UsageError for bad values.
struct SupportTestOptions {
    double max_gap = 1;
    Extrapolate extrapolate = Extrapolate::nan;
};
SupportTestOptions support_test_options(const Args& a);

/// --memory BYTES of the field queries (probe, resample): a point store's slab budget.
void add_store_memory_option(Args& a);
/// A single point store (.mlc) queried through the mpu field (not a .mlf): what runs slab by slab
/// within --memory (stream/store_field_queries.hpp). With `warn`, a --memory given to any other
/// input is a warning on stderr: the points and their field are then held whole.
bool queries_store_slabs(const Args& a, bool warn = true);
/// The field, support test and --memory budget (default: the memory this process may use) of a
/// store's slab queries.
StoreQueryParams store_query_params(const Args& a);

/// For commands without the data: the .mlf named by --field, loaded (no coverage). UsageError when
/// --field names a field kind instead of a file.
BuiltField load_field_arg(const Args& a);

}  // namespace meshless::cli
