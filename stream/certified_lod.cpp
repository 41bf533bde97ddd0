#include "stream/certified_lod.hpp"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_reduce.h>
#include <oneapi/tbb/blocked_range.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "formats/cluster_tree_file.hpp"
#include "formats/field_hint.hpp"
#include "formats/point_set_writer.hpp"
#include "formats/terminal_safe.hpp"
#include "kernels/sample_set_hash.hpp"
#include "kernels/cluster_lod.hpp"
#include "kernels/errors.hpp"
#include "kernels/make_field.hpp"

namespace meshless {

namespace {

/// The largest |field - value| over the samples (inf where the field is NaN), evaluated in batches.
double max_error_at(const Field& f, const PointSet& s) {
    constexpr std::size_t kBatch = 4096;
    const std::size_t n = s.size();
    return oneapi::tbb::parallel_reduce(
        oneapi::tbb::blocked_range<std::size_t>(0, n, kBatch), 0.0,
        [&](const oneapi::tbb::blocked_range<std::size_t>& r, double m) {
            std::vector<double> v(r.size());
            f.evaluate(std::span<const Vec3>(s.pos.data() + r.begin(), r.size()), v, {});
            for (std::size_t i = 0; i < r.size(); ++i) {
                const double d = std::abs(v[i] - s.value[r.begin() + i]);
                m = std::max(m, std::isnan(d) ? std::numeric_limits<double>::infinity() : d);
            }
            return m;
        },
        [](double a, double b) { return std::max(a, b); });
}

/// The finite samples of `samples`, checked to be the tree's (InvalidArgument otherwise).
PointSet tree_samples_checked(const ClusterTree& tree, const PointSet& samples) {
    PointSet finite;
    finite.value_name = samples.value_name;
    finite.pos.reserve(samples.size());
    finite.value.reserve(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const Vec3& p = samples.pos[i];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(samples.value[i])) {
            finite.pos.push_back(p);
            finite.value.push_back(samples.value[i]);
        }
    }
    finite.blocks.push_back(PointSetBlock{"samples", {static_cast<std::int64_t>(finite.size()), 1, 1}, 0, finite.size()});
    if (finite.size() != tree.stats.samples)
        throw InvalidArgument("the samples are not the tree's: " + std::to_string(finite.size()) + " finite samples, the tree has " +
                              std::to_string(tree.stats.samples));
    const auto b = finite.bounds();
    for (int k = 0; k < 3; ++k) {
        const double lo[2] = {b[0][k], tree.bounds[0][k]}, hi[2] = {b[1][k], tree.bounds[1][k]};
        if (lo[0] != lo[1] || hi[0] != hi[1]) throw InvalidArgument("the samples are not the tree's: their bounds differ");
    }
    // (trees before file version 4 record no hash: their count and bounds are all there is to check)
    if (tree.samples_hash != 0 && sample_set_hash(finite.pos, finite.value) != tree.samples_hash)
        throw InvalidArgument("the samples are not the tree's: the same count and bounds, other positions or values (their hash differs)");
    return finite;
}

/// The certified error of LOD(n): the mpu field of its points evaluated at every sample; `lod` gets the points.
double lod_error(const ClusterTree& tree, const PointSet& finite, std::uint64_t n, const FieldParams& field, PointSet& lod) {
    lod = lod_point_set(tree.nodes, LodMode::count, static_cast<double>(n), tree.value_name);
    // a field needs 4 distinct points: a LOD of fewer reconstructs nothing, its error is +inf
    if (lod.size() < 4) return std::numeric_limits<double>::infinity();
    std::unique_ptr<Field> f;
    try {
        f = make_field(lod, field);
    } catch (const FormatError&) {  // fewer than 4 distinct points once near-duplicates are merged
        return std::numeric_limits<double>::infinity();
    }
    return max_error_at(*f, finite);
}

}  // namespace

CertifiedLod certified_lod(const ClusterTree& tree, const PointSet& samples, double max_error, const FieldParams& field, int threads,
                           const std::function<void(std::uint64_t, double)>& trial, std::optional<CertifiedError> known) {
    if (!std::isfinite(max_error) || max_error < 0) throw InvalidArgument("certified LOD: the error must be a finite number >= 0");
    // the samples the tree was built from: the same count of finite samples and the same bounds
    const PointSet finite = tree_samples_checked(tree, samples);
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(std::max(1, threads)));
    CertifiedLod out;
    out.samples = finite.size();
    auto error_of = [&](std::uint64_t n, PointSet& lod) {
        const double e = lod_error(tree, finite, n, field, lod);
        ++out.trials;
        if (trial) trial(n, e);
        return e;
    };
    const std::uint64_t leaves = tree.stats.splits + 1;
    PointSet best;
    double best_error = 0;
    std::uint64_t lo = 1, hi = leaves;
    if (known && known->max_error <= max_error && known->count >= 1 && known->count <= leaves) {
        // a size certified within E already: the search runs below it, the finest need not be tried
        hi = known->count;
        best = lod_point_set(tree.nodes, LodMode::count, static_cast<double>(hi), tree.value_name);
        best_error = known->max_error;
    } else {
        best_error = error_of(leaves, best);
    }
    if (best_error <= max_error) {
        while (lo < hi) {
            const std::uint64_t mid = lo + (hi - lo) / 2;
            PointSet lod;
            const double e = error_of(mid, lod);
            if (e <= max_error) {
                hi = mid;
                best = std::move(lod);
                best_error = e;
            } else {
                lo = mid + 1;
            }
        }
        out.reached = true;
    }
    out.count = best.size();
    out.max_error = best_error;
    out.points = std::move(best);
    return out;
}

std::vector<std::uint64_t> certify_counts(const ClusterTree& tree, std::span<const double> fractions) {
    const std::uint64_t leaves = tree.stats.splits + 1;
    std::vector<std::uint64_t> counts;
    for (double f : fractions) {
        if (!(f > 0 && f <= 1)) throw InvalidArgument("certified LOD: a fraction of the samples must lie in (0, 1]");
        const double n = std::round(f * static_cast<double>(tree.stats.samples));
        counts.push_back(std::clamp<std::uint64_t>(static_cast<std::uint64_t>(std::max(1.0, n)), 1, leaves));
    }
    std::sort(counts.begin(), counts.end());
    counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
    if (counts.size() > kMaxCertifiedErrors)
        throw InvalidArgument("certified LOD: at most " + std::to_string(kMaxCertifiedErrors) + " sizes, got " + std::to_string(counts.size()));
    return counts;
}

std::vector<CertifiedError> certify_lod_sizes(const ClusterTree& tree, const PointSet& samples, std::span<const std::uint64_t> counts,
                                              double hardy_c_rel, int threads, const std::function<void(std::uint64_t, double)>& trial) {
    if (!(hardy_c_rel > 0 && hardy_c_rel <= 100)) throw InvalidArgument("certified LOD: Hardy's c must lie in (0, 100]");
    const PointSet finite = tree_samples_checked(tree, samples);
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(std::max(1, threads)));
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    fp.hardy_c_rel = hardy_c_rel;
    std::vector<CertifiedError> out;
    for (std::uint64_t n : counts) {
        if (n < 1 || n > tree.stats.splits + 1 || (!out.empty() && n <= out.back().count))
            throw InvalidArgument("certified LOD: counts must ascend within 1.." + std::to_string(tree.stats.splits + 1));
        PointSet lod;
        const double e = lod_error(tree, finite, n, fp, lod);
        out.push_back(CertifiedError{n, e, hardy_c_rel});
        if (trial) trial(n, e);
    }
    return out;
}

CertifiedLod run_certified_lod_job(const CertifiedLodJob& job) {
    const ClusterTree t = read_cluster_tree_file(job.tree_path);
    FieldParams fp;  // the mpu field (section 5.5) with the c a reader of the LOD's file uses
    fp.kind = FieldKind::mpu;
    fp.hardy_c_rel = job.hardy_c_rel ? *job.hardy_c_rel : lod_hardy_c_rel(t.params.order == CbtSplitOrder::max_error);
    const PointSet samples = read_tree_samples(job.samples);
    const std::string& samples_path = job.samples.paths.front();
    const auto t0 = std::chrono::steady_clock::now();
    const double expected = std::log2(static_cast<double>(t.stats.splits + 1)) + 2;
    // the smallest size the tree certified within E with this field, if any (hierarchy --certify)
    std::optional<CertifiedError> known;
    for (const CertifiedError& e : t.certified)
        if (e.hardy_c_rel == fp.hardy_c_rel && e.max_error <= job.max_error) {
            known = e;
            break;
        }
    CertifiedLod c;
    int trials = 0;
    try {
        c = certified_lod(t, samples, job.max_error, fp, job.threads, [&](std::uint64_t, double) {
            if (job.progress) job.progress(++trials, expected);
        }, known);
    } catch (const InvalidArgument& x) {
        throw FormatError(samples_path + ": " + x.what() + " (" + job.tree_path + ")");
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string path = terminal_safe(job.tree_path);
    if (!c.reached && job.warnings)
        std::fprintf(job.warnings, "meshless lod: warning: %s: no level of detail reaches --max-error %g: the finest (%llu points) is within %g\n",
                     path.c_str(), job.max_error, static_cast<unsigned long long>(c.count), c.max_error);
    char desc[160];
    std::snprintf(desc, sizeof desc, "certified max error %.17g (asked %.17g) at %llu samples, count %llu", c.max_error, job.max_error,
                  static_cast<unsigned long long>(c.samples), static_cast<unsigned long long>(c.count));
    write_point_set(job.out, c.points, {"meshless lod " + std::string(desc) + " of " + job.tree_path, field_hint_line(fp.hardy_c_rel)});
    if (job.stats)
        std::fprintf(job.stats, "lod: %s: %llu points, max error %g over %llu samples (asked %g), %d trials, %.3f s\n", path.c_str(),
                     static_cast<unsigned long long>(c.count), c.max_error, static_cast<unsigned long long>(c.samples), job.max_error,
                     c.trials, secs);
    return c;
}

}  // namespace meshless
