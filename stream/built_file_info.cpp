#include "stream/built_file_info.hpp"

#include <cinttypes>
#include <cstdint>
#include <vector>

#include "formats/cluster_tree_file.hpp"
#include "formats/field_file.hpp"
#include "formats/ply.hpp"
#include "formats/terminal_safe.hpp"
#include "kernels/cluster_lod.hpp"

namespace meshless {

namespace {

/// Error thresholds for the info table: the root's error times 1/2^k down to the reached error.
std::vector<double> error_thresholds(const ClusterTree& t) {
    std::vector<double> e;
    const double top = t.nodes[0].error;
    for (double v = top; v > t.stats.error_reached && e.size() < 10; v *= 0.5) e.push_back(v);
    e.push_back(t.stats.error_reached);
    return e;
}

}  // namespace

void describe_field_file(const std::string& path, std::FILE* out) {
    const FieldFile ff = read_field_file(path);
    const FieldFileInfo& i = ff.info;
    const FieldParams& p = i.params;
    const FieldBuildStats& s = i.stats;
    const PointSetIdentity& id = i.data.identity;
    auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
    std::fprintf(out, "%s: meshless fitted field (.mlf), format version %u, %llu bytes (checked)\n", terminal_safe(path).c_str(),
                 i.version, u(i.file_bytes));
    std::fprintf(out, "  field: %s\n", std::string(field_kind_name(p.kind)).c_str());
    std::string c = p.hardy_c_world > 0 ? std::to_string(p.hardy_c_world) + " (world units)"
                                        : std::to_string(p.hardy_c_rel) + " x bounding-box diagonal";
    switch (p.kind) {
        case FieldKind::rbf_grid:
            std::fprintf(out, "  parameters: binning m = %g, support %s, local points %u..%u, nearest K = %s, Hardy c = %s\n",
                         p.binning_m, p.rbf_grid_support == RbfGridSupport::paper_radius ? "paper radius" : "27 neighbours",
                         p.rbf_grid_min_local, p.rbf_grid_max_local,
                         p.rbf_grid_local_points == 0 ? "all" : std::to_string(p.rbf_grid_local_points).c_str(), c.c_str());
            break;
        case FieldKind::mpu:
            std::fprintf(out, "  parameters: N = %u, min points %u, alpha = %g, max depth %u, Hardy c = %s\n", p.mpu_max_points,
                         p.mpu_min_points, p.mpu_alpha, p.mpu_max_depth, c.c_str());
            break;
        case FieldKind::global_rbf:
            std::fprintf(out, "  parameters: at most %u points, Hardy c = %s\n", p.global_max_points, c.c_str());
            break;
    }
    std::fprintf(out, "  merge: points closer than %g x mean spacing%s\n", p.merge_rel, p.normalise_axes ? ", axes normalised" : "");
    std::fprintf(out, "  fitted to: %llu points, identity hash %016llx\n", u(id.count), u(id.hash));
    std::fprintf(out, "  bounds: %.12g %.12g %.12g .. %.12g %.12g %.12g\n", id.bounds[0].x, id.bounds[0].y, id.bounds[0].z,
                 id.bounds[1].x, id.bounds[1].y, id.bounds[1].z);
    if (i.data.has_values)
        std::fprintf(out, "  value: %s, range %.9g .. %.9g\n",
                     i.data.value_name.empty() ? "(unnamed)" : ply_escape(i.data.value_name, 128).c_str(), id.value_range[0],
                     id.value_range[1]);
    else
        std::fprintf(out, "  value: none (positions only)\n");
    std::fprintf(out, "  dropped by the reader: %llu NaN/Inf, %llu blanked\n", u(i.data.dropped_nonfinite),
                 u(i.data.dropped_blanked));
    std::fprintf(out, "  build: %llu points used (%llu merged, tolerance %g), c = %g, %llu local interpolants (%llu exact, "
                 "%llu rank-deficient, %llu regularised, %llu linear fallback, %llu polynomial only, %llu grown, %llu capped), "
                 "%.1f points per local (max %llu)\n",
                 u(s.used_points), u(s.merged_points), s.merge_tolerance, s.hardy_c_world, u(s.locals), u(s.interpolated),
                 u(s.rank_deficient), u(s.regularised), u(s.linear_fallback), u(s.polynomial_only), u(s.grown), u(s.capped),
                 s.mean_local_points, u(s.max_local_points));
    if (p.kind == FieldKind::rbf_grid)
        std::fprintf(out, "  RBF grid: %lld x %lld x %lld cells\n", static_cast<long long>(s.grid_dims[0]),
                     static_cast<long long>(s.grid_dims[1]), static_cast<long long>(s.grid_dims[2]));
    if (p.kind == FieldKind::mpu) std::fprintf(out, "  octree: %llu nodes, depth %u\n", u(s.octree_nodes), s.octree_depth);
    std::fprintf(out, "  memory when loaded: %.1f MiB\n", s.memory_bytes / 1048576.0);
    std::fprintf(out, "  sections: %zu\n", i.sections.size());
    for (const auto& sec : i.sections) {
        static const char* const kType[] = {"bytes", "f64", "i64", "u32", "i32"};
        std::fprintf(out, "    %-14s %-5s %12llu elements, %12llu bytes%s\n", terminal_safe(sec.name).c_str(),
                     kType[sec.type < 5 ? sec.type : 0], u(sec.count), u(sec.stored_bytes),
                     sec.compressed ? (" (zstd" + std::string(sec.shuffled ? ", shuffled" : "") + ", from " +
                                       std::to_string(sec.raw_bytes) + ")").c_str()
                                    : "");
    }
}

void describe_cluster_tree(const std::string& path, std::FILE* out) {
    const ClusterTree t = read_cluster_tree_file(path);
    const CbtStats& s = t.stats;
    const CbtParams& p = t.params;
    std::fprintf(out, "%s: cluster binary tree (.mlh version %u, dissertation chapter 6)\n", terminal_safe(path).c_str(),
                 cluster_tree_file_version(path));
    std::fprintf(out, "  samples: %" PRIu64 " (%" PRIu64 " NaN/Inf dropped), value '%s' %g .. %g\n", s.samples,
                 s.dropped_nonfinite, terminal_safe(t.value_name).c_str(), t.value_range[0], t.value_range[1]);
    std::fprintf(out, "  bounds: (%g, %g, %g) .. (%g, %g, %g)\n", t.bounds[0].x, t.bounds[0].y, t.bounds[0].z, t.bounds[1].x,
                 t.bounds[1].y, t.bounds[1].z);
    std::fprintf(out, "  nodes: %zu, splits: %" PRIu64 ", skipped splits: %" PRIu64 ", depth: %u\n", t.nodes.size(), s.splits,
                 s.skipped, s.depth);
    std::fprintf(out, "  error: root %g, reached %g (the finest level of detail, %" PRIu64 " leaves)\n", t.nodes[0].error,
                 s.error_reached, (t.nodes.size() + 1) / 2);
    std::fprintf(out, "  built with: split order %s (size term %g), cluster value %s, neighbours %u, Hardy's c %g (world), min cluster %u, PCA scaling %s, ",
                 split_order_name(p.order), p.size_term, cluster_value_name(p.value), p.neighbours, s.hardy_c_world, p.min_cluster,
                 pca_scaling_name(p.scaling));
    if (p.max_splits == UINT64_MAX) std::fprintf(out, "max splits none, ");
    else std::fprintf(out, "max splits %" PRIu64 ", ", p.max_splits);
    std::fprintf(out, "max error %g\n", p.max_error);
    const auto per_level = lod_sizes_per_level(t.nodes);
    std::fprintf(out, "  level-based LODs (meshless lod --level L):\n    %6s %12s %9s\n", "level", "points", "% samples");
    for (std::size_t L = 0; L < per_level.size(); ++L)
        std::fprintf(out, "    %6zu %12" PRIu64 " %8.2f%%\n", L, per_level[L], 100.0 * per_level[L] / s.samples);
    std::fprintf(out, "  error-based LODs (meshless lod --error E):\n    %12s %12s %9s\n", "error", "points", "% samples");
    for (double e : error_thresholds(t)) {
        const std::uint64_t n = lod_size_at_error(t.nodes, e);
        std::fprintf(out, "    %12.6g %12" PRIu64 " %8.2f%%\n", e, n, 100.0 * n / s.samples);
    }
    if (t.certified.empty()) {
        std::fprintf(out, "  certified errors: none (meshless hierarchy --certify F1,F2,... stores them)\n");
        return;
    }
    std::fprintf(out, "  certified errors (meshless lod --count N: the mpu field of its points at every sample; inf: the field is\n"
                      "  undefined at some sample, or the level of detail has fewer than 4 distinct points):\n"
                      "    %12s %9s %14s %9s\n", "points", "% samples", "max error", "Hardy c");
    for (const CertifiedError& c : t.certified)
        std::fprintf(out, "    %12" PRIu64 " %8.2f%% %14.6g %9g\n", c.count, 100.0 * static_cast<double>(c.count) / static_cast<double>(s.samples),
                     c.max_error, c.hardy_c_rel);
}

}  // namespace meshless
