#include "stream/field_data.hpp"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>

#include "formats/binary_file.hpp"
#include "formats/cluster_tree_file.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/terminal_safe.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "kernels/make_field.hpp"
#include "kernels/point_set_identity.hpp"
#include "kernels/structured_block.hpp"
#include "stream/field_evaluation.hpp"

namespace meshless {

bool all_multiblock(const std::vector<std::string>& paths) {
    return !paths.empty() && std::all_of(paths.begin(), paths.end(), [](const std::string& p) { return looks_like_multiblock(p); });
}

std::string data_field_default(const std::vector<std::string>& paths) {
    return all_multiblock(paths) ? kBlocksFieldDefault : kPointsFieldDefault;
}

namespace {
PointSet read_any_points(const std::vector<std::string>& paths, const PointSetOptions& options, const std::string& command,
                         const InputWarning& warn) {
    for (const auto& p : paths)  // the point-set readers go by the file's extension (and some reread it)
        if (p == "-")
            throw InvalidArgument("-: meshless " + command + " reads its data (point sets, volumes, multiblock sets) from files "
                                  "(their names and contents say the format), not from standard input");
    if (all_multiblock(paths)) return to_point_set(read_multiblock(paths, options));
    if (paths.size() > 1)  // volumes read as points (their voxels) would be mixed into one set
        for (const auto& p : paths)
            if (looks_like_volume(p) && !looks_like_multiblock(p) && !looks_like_point_set(p))
                throw InvalidArgument(p + " is a volume: meshless " + command + " takes one volume, or point sets (several are "
                                      "one set), or the blocks of one multiblock grid");
    const bool tree = std::any_of(paths.begin(), paths.end(), [](const std::string& p) { return is_cluster_tree_file(p); });
    if (!tree && (options.lod_level || options.lod_error || options.lod_count || options.lod_fraction))
        throw InvalidArgument(std::string("--") +
                              (options.lod_level   ? "lod-level"
                               : options.lod_error ? "lod-error"
                               : options.lod_count ? "lod-count"
                                                   : "lod-fraction") +
                              " picks a level of detail of a cluster tree (.mlh); " + paths.front() + " is none");
    for (const auto& p : paths)  // a level of detail of a cluster tree beyond the tree: say so
        if (is_cluster_tree_file(p)) {
            const ClusterTreeLodRequest r = cluster_tree_lod_request(read_cluster_tree_file(p), options);
            if (r.clamped && warn) warn(p, r.note);
        }
    return read_point_set(paths, options);
}
}  // namespace

PointSet read_field_points(const std::vector<std::string>& paths, const PointSetOptions& options, const std::string& command,
                           const InputWarning& warn, bool warn_dropped) {
    PointSet ps = read_any_points(paths, options, command, warn);
    std::string names;
    for (const auto& p : paths) names += (names.empty() ? "" : ", ") + p;
    if (warn && warn_dropped && ps.dropped_nonfinite > 0)
        warn(names, std::to_string(ps.dropped_nonfinite) + " points with a NaN/Inf position or value dropped (--strict refuses them)");
    // every command that reads points this way fits, probes, renders or clusters their values
    if (!ps.has_values)
        throw FormatError(names + ": the points carry no values (positions only); meshless " + command +
                          " needs a value at each point");
    return ps;
}

std::unique_ptr<Field> fit_data_field(const PointSet& points, const FieldParams& params, const std::string& inputs, int threads,
                                      FieldBuildStats* stats, const FieldProgress& progress, const FitShare* share) {
    return with_error_prefix(inputs, inputs + ": ", [&] { return fit_field(points, params, threads, stats, progress, share); });
}

BuiltField load_built_field(const std::string& path) {
    const auto t0 = std::chrono::steady_clock::now();
    FieldFile ff = read_field_file(path);
    BuiltField f;
    f.load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    f.field = std::move(ff.field);
    f.file = std::move(ff.info);
    return f;
}

FittedData write_fitted_field(const std::string& path, const Field& field, const FieldParams& params, const PointSet& points,
                              const FieldBuildStats& stats, int zstd_level) {
    FittedData data;
    data.identity = point_set_identity(points);
    data.dropped_nonfinite = points.dropped_nonfinite;
    data.dropped_blanked = points.dropped_blanked;
    data.has_values = points.has_values;
    data.value_name = points.value_name;
    write_field_file(path, field, params, data, stats, zstd_level);
    return data;
}

void print_field_build_report(std::FILE* out, const std::string& command, const FieldParams& params, const PointSet& points,
                              const FieldBuildStats& st) {
    using ull = unsigned long long;
    const char* cmd = command.c_str();
    std::fprintf(out,
                 "%s: %s field from %llu points (%llu dropped by the reader as NaN/Inf, %llu blanked; %llu merged as "
                 "near-duplicates), c = %g, %llu local interpolants "
                 "(%llu exact, %llu rank-deficient, %llu regularised, %llu linear fallback), %.1f MiB, %.3f s\n",
                 cmd, std::string(field_kind_name(params.kind)).c_str(), ull(st.input_points), ull(points.dropped_nonfinite),
                 ull(points.dropped_blanked), ull(st.merged_points), st.hardy_c_world, ull(st.locals), ull(st.interpolated),
                 ull(st.rank_deficient), ull(st.regularised), ull(st.linear_fallback), st.memory_bytes / 1048576.0,
                 st.build_seconds);
    if (st.c_lowered > 0 || st.refitted > 0)
        std::fprintf(out,
                     "%s: %llu local fits took a c below the global one (at most %g x their point spacing; mean c %g), "
                     "%llu of them kept the fit with %g x their spacing (smaller leave-one-out error)\n",
                     cmd, ull(st.c_lowered), params.hardy_c_spacing, st.mean_local_c, ull(st.refitted), params.hardy_c_rough);
    if (st.spanned > 0)
        std::fprintf(out, "%s: %llu local fits had their points in one plane or line and took the nearest points off it\n", cmd,
                     ull(st.spanned));
}

void print_field_load_report(std::FILE* out, const std::string& command, const std::string& path, const FieldFileInfo& i,
                             double seconds) {
    std::fprintf(out,
                 "%s: %s field loaded from %s (%.1f MiB): fitted to %" PRIu64 " points (%" PRIu64
                 " merged), %" PRIu64 " local interpolants, %.3f s\n",
                 command.c_str(), std::string(field_kind_name(i.params.kind)).c_str(), path.c_str(), i.file_bytes / 1048576.0,
                 i.data.identity.count, i.stats.merged_points, i.stats.locals, seconds);
}

void print_fit_report(std::FILE* out, const std::string& path, const FittedData& data, const FieldBuildStats& st, double read_seconds,
                      double write_seconds) {
    std::fprintf(out, "fit: read %.3f s, fit %.3f s, wrote %s (%" PRIu64 " bytes, identity %s) in %.3f s\n", read_seconds,
                 st.build_seconds, terminal_safe(path).c_str(), regular_file_size(path), describe_identity(data.identity).c_str(),
                 write_seconds);
}

}  // namespace meshless
