#include "stream/cluster_hierarchy.hpp"

#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cinttypes>
#include <cstdio>

#include "formats/cluster_tree_file.hpp"
#include "formats/field_hint.hpp"
#include "formats/point_set_writer.hpp"
#include "formats/terminal_safe.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/brick_store_point_set.hpp"
#include "kernels/cluster_lod.hpp"
#include "kernels/errors.hpp"
#include "stream/text_format.hpp"

namespace meshless {

double cluster_hierarchy_split_bound(const CbtParams& p, std::size_t samples) {
    return std::min<double>(static_cast<double>(p.max_splits), std::max<double>(1, static_cast<double>(samples) - 1));
}

bool cluster_hierarchy_counts_settled(const CbtParams& p, std::size_t samples) {
    return p.max_error > 0 && static_cast<double>(p.max_splits) >= static_cast<double>(samples) - 1;
}

double cluster_hierarchy_progress(const CbtParams& p, std::size_t samples, const CbtProgressReport& b) {
    const double bound = cluster_hierarchy_split_bound(p, samples);
    if (cluster_hierarchy_counts_settled(p, samples)) {
        const double settled = samples > 0 ? static_cast<double>(b.settled) / static_cast<double>(samples) : 1;
        const double applied = b.computed > 0 ? static_cast<double>(b.applied) / static_cast<double>(b.computed) : 0;
        return std::clamp(0.5 * settled + 0.5 * applied, 0.0, 1.0);
    }
    const double work = static_cast<double>(samples) * std::log2(bound + 1);
    return std::clamp(0.5 * std::min(1.0, static_cast<double>(b.work) / work) + 0.5 * static_cast<double>(b.applied) / bound, 0.0, 1.0);
}

ClusterTree build_cluster_hierarchy(const PointSet& points, const CbtParams& p, int threads, const std::string& input,
                                    const std::function<void(const CbtProgressReport&)>& progress) {
    ClusterTree tree;
    {
        oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
        struct Report final : CbtProgress {
            const std::function<void(const CbtProgressReport&)>& f;
            explicit Report(const std::function<void(const CbtProgressReport&)>& fn) : f(fn) {}
            void splits_done(const CbtProgressReport& r) override {
                if (f) f(r);
            }
        } report(progress);
        try {
            tree = build_cluster_tree(points.pos, points.value, p, &report);
        } catch (const InvalidArgument& e) {  // the data cannot make a tree: a data error naming the input
            std::string msg = e.what();
            if (msg.rfind("cluster tree: ", 0) == 0) msg = msg.substr(14);
            throw FormatError(input + ": " + msg);
        }
    }
    tree.stats.dropped_nonfinite += points.dropped_nonfinite;
    tree.value_name = points.value_name;
    return tree;
}

std::vector<std::string> cluster_hierarchy_notes(const ClusterTree& tree, const CbtParams& p) {
    std::vector<std::string> notes;
    const CbtStats& s = tree.stats;
    if (s.dropped_nonfinite)
        notes.push_back(format_text("warning: %" PRIu64 " samples with NaN/Inf positions or values dropped", s.dropped_nonfinite));
    if (tree.nodes.size() == 1) {
        if (p.max_splits == 0)
            notes.push_back(format_text("note: --max-splits 0: no split made (error %g): a one-node tree", tree.nodes[0].error));
        else
            notes.push_back(format_text("note: one cluster (error %g <= --max-error %g, or nothing to split): a one-node tree",
                                   tree.nodes[0].error, p.max_error));
    }
    return notes;
}

std::string cluster_hierarchy_report(const ClusterTree& tree, const CbtParams& p, int threads, double read_seconds,
                                     double write_seconds) {
    const CbtStats& s = tree.stats;
    return format_text("hierarchy: %" PRIu64 " samples, %" PRIu64 " splits, %" PRIu64 " skipped, depth %u, %zu nodes, error %g -> %g, "
                  "split order %s (size term %g), cluster value %s, c = %g, PCA %s, %d thread%s: read %.3f s, build %.3f s, write %.3f s, %.1f MiB in the builder, "
                  "%" PRIu64 " splits made ahead and not applied, %" PRIu64 " rounds",
                  s.samples, s.splits, s.skipped, s.depth, tree.nodes.size(), tree.nodes[0].error, s.error_reached,
                  split_order_name(p.order), p.size_term, cluster_value_name(p.value), s.hardy_c_world, pca_scaling_name(p.scaling), threads, threads == 1 ? "" : "s", read_seconds, s.seconds,
                  write_seconds, s.memory_bytes / 1048576.0, s.speculative_unused, s.rounds);
}

LodExtraction extract_lod(const ClusterTree& t, const ClusterTreeLodRequest& r) {
    LodExtraction e;
    const auto t0 = std::chrono::steady_clock::now();
    e.points = lod_point_set(t.nodes, r.mode, r.threshold, t.value_name);
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    e.lo = t.value_range[0];
    e.hi = t.value_range[1];
    for (const double v : e.points.value)
        if (v < t.value_range[0] || v > t.value_range[1]) {
            ++e.outside;
            e.lo = std::min(e.lo, v);
            e.hi = std::max(e.hi, v);
        }
    return e;
}

std::string lod_overshoot_warning(const ClusterTree& t, const LodExtraction& e) {
    if (e.outside == 0) return {};
    return format_text("warning: %zu of %zu cluster values lie outside the samples' range [%g, %g] (from %g to %g): "
                  "the clusters' fits overshoot there",
                  e.outside, e.points.size(), t.value_range[0], t.value_range[1], e.lo, e.hi);
}

std::string lod_report(const ClusterTree& t, const ClusterTreeLodRequest& r, const std::string& path, const LodExtraction& e) {
    return format_text("lod: %s of %s: %zu points (%.2f%% of %" PRIu64 " samples), %.4f s", r.description.c_str(),
                  terminal_safe(path).c_str(), e.points.size(), 100.0 * e.points.size() / t.stats.samples, t.stats.samples,
                  e.seconds);
}

PointSet read_tree_samples(const TreeSamplesInput& in) {
    if (in.raw_given && in.paths.size() != 1)
        throw InvalidArgument("--dims/--type/--spacing/--series/--array: one volume, not " + std::to_string(in.paths.size()) + " inputs");
    if (in.paths.size() == 1 && is_brick_store(in.paths.front())) {
        if (in.array_given) throw InvalidArgument("--array: " + in.paths.front() + " is a brick store (.mlb), which holds one unnamed array");
        return point_set_from_brick_store(in.paths.front());
    }
    if (in.raw_given) return point_set_from_volume(in.paths.front(), in.points, in.raw);
    return read_field_points(in.paths, in.points, in.command, in.warn, /*warn_dropped=*/false);
}

LodExtraction run_lod_job(const std::string& tree_path, const PointSetOptions& request, const std::string& out, std::FILE* warnings,
                          std::FILE* stats) {
    const ClusterTree t = read_cluster_tree_file(tree_path);
    const ClusterTreeLodRequest r = cluster_tree_lod_request(t, request);
    if (r.clamped && warnings)
        std::fprintf(warnings, "meshless lod: warning: %s: %s\n", terminal_safe(tree_path).c_str(), terminal_safe(r.note).c_str());
    LodExtraction e = extract_lod(t, r);
    if (const std::string w = lod_overshoot_warning(t, e); !w.empty() && warnings) std::fprintf(warnings, "meshless lod: %s\n", w.c_str());
    const std::vector<std::string> comments = {"meshless lod " + r.description + " of " + tree_path,
                                               field_hint_line(lod_hardy_c_rel(t.params.order == CbtSplitOrder::max_error))};
    write_point_set(out, e.points, comments);
    if (stats) std::fprintf(stats, "%s\n", lod_report(t, r, tree_path, e).c_str());
    return e;
}

}  // namespace meshless
