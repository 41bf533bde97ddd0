#include "stream/store_slab_runner.hpp"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "kernels/errors.hpp"
#include "kernels/mpu_fit_cache.hpp"
#include "stream/seconds_since.hpp"
#include "stream/store_slab.hpp"

namespace meshless {

namespace {

constexpr double kNoSlabAbove = std::numeric_limits<double>::infinity();

std::string budget_mib(double bytes) { return std::to_string(static_cast<std::uint64_t>(std::ceil(bytes / 1048576.0))) + " MiB"; }


}  // namespace

void for_each_store_slab(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                         const std::array<Vec3, 2>& query_xy, const SlabLayers& q, int threads, StoreQueryReport& rep) {
    if (p.field.kind != FieldKind::mpu) throw InvalidArgument("a point store is queried slab by slab with the mpu field only");
    const StoreBrickIndex index(store);
    // (what the work holds throughout is not the slabs')
    const double budget = static_cast<double>(p.memory_bytes) - p.fixed_bytes - 4.0 * static_cast<double>(plan.cell_table.size());
    MpuFitCache cache;
    // A slab's field holds the fits of the leaves meeting its query box, not of its halo: its bytes
    // go with the points of the query range (the most a point there took so far), the rest of the
    // loaded points cost other_bytes_per_point each; bytes_per_point a loaded point until a field is built.
    double field_per_query_point = 0;
    const std::vector<char> no_bricks(store.bricks().size(), 0);
    const auto query_points = [&](std::int64_t k0, std::int64_t k1) {
        return static_cast<double>(store_slab(store, plan, q.range(k0, k1), 0, no_bricks).points);
    };
    const auto need = [&](const StoreSlab& s, std::int64_t k0, std::int64_t k1) {
        const double loaded = static_cast<double>(s.points);
        const double points = field_per_query_point > 0
                                  ? loaded * p.other_bytes_per_point + 1.1 * field_per_query_point * query_points(k0, k1)
                                  : loaded * p.bytes_per_point;
        return points + q.bytes(k0, k1) + 2.0 * static_cast<double>(cache.bytes());
    };
    const double halo0 = store_first_halo(plan, p.field);
    std::vector<std::pair<Vec3, double>> seen;
    for (std::int64_t k0 = 0; k0 < q.count;) {
        double halo = halo0;
        // (the lacking balls of earlier slabs reach on into a rising run's next slabs)
        std::vector<char> extra = q.descending ? std::vector<char>(store.bricks().size(), 0)
                                               : bricks_still_lacking(store, index, seen, q.range(k0, k0 + 1)[0] - halo0);
        const auto slab_of = [&](std::int64_t k1) { return store_slab(store, plan, q.range(k0, k1), halo, extra); };
        // the most layers the estimate lets in: doubling, then bisection
        std::int64_t k1 = k0 + 1, step = 1;
        while (k1 < q.count && need(slab_of(std::min(q.count, k1 + step)), k0, std::min(q.count, k1 + step)) <= budget) {
            k1 = std::min(q.count, k1 + step);
            step *= 2;
        }
        for (step /= 2; step > 0; step /= 2)
            if (k1 + step <= q.count && need(slab_of(k1 + step), k0, k1 + step) <= budget) k1 += step;
        for (;;) {
            const StoreSlab slab = slab_of(k1);
            PointSet points = load_store_slab(store, slab, rep.read_seconds);
            rep.loaded += points.size();
            rep.most_loaded = std::max<std::uint64_t>(rep.most_loaded, points.size());
            StoreSlabRegion slab_region(store, plan, index, slab, query_xy);
            FieldRegion& region = slab_region.region;
            const double others = static_cast<double>(points.size()) * p.other_bytes_per_point + q.bytes(k0, k1) +
                                  2.0 * static_cast<double>(cache.bytes());
            region.max_field_bytes = static_cast<std::uint64_t>(std::max(1.0, budget - others));
            FieldBuildStats fst;
            std::unique_ptr<MpuField> field;
            std::unique_ptr<PointCoverage> coverage;
            const auto t0 = std::chrono::steady_clock::now();
            {
                oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
                oneapi::tbb::parallel_invoke(
                    [&] {
                        // the fits reaching into the next slab's range are kept for it
                        if (q.descending) cache.begin(k1 < q.count ? q.range(k1, k1 + 1)[1] : -kNoSlabAbove, /*falling=*/true);
                        else cache.begin(k1 < q.count ? q.range(k1, k1 + 1)[0] : kNoSlabAbove);
                        field = std::make_unique<MpuField>(points, p.field, &fst, FieldProgress{}, nullptr, &region, &cache);
                    },
                    [&] {
                        if (p.max_gap > 0) coverage = std::make_unique<PointCoverage>(points.pos, points.value, p.max_gap);
                    });
            }
            rep.field_seconds += seconds_since(t0);
            field_per_query_point =
                std::max(field_per_query_point, static_cast<double>(fst.memory_bytes) / std::max(1.0, query_points(k0, k1)));
            if (!field->region_exact()) {  // load the bricks the lacking balls meet, and build again
                if (add_lacking_bricks(*field, index, extra, seen) == 0) halo *= 2;
                ++rep.retries;
                continue;
            }
            if (field->over_budget()) {  // fewer layers, as many as the field's size allows; or no kept fits
                ++rep.retries;
                const double room = static_cast<double>(region.max_field_bytes) / static_cast<double>(fst.memory_bytes);
                if (k1 > k0 + 1) {
                    k1 = std::min(k1 - 1, k0 + std::max<std::int64_t>(1, static_cast<std::int64_t>(static_cast<double>(k1 - k0) * room * 0.95)));
                    continue;
                }
                if (cache.bytes() > 0) {
                    cache.clear();
                    continue;
                }
                throw InvalidArgument("--memory " + budget_mib(static_cast<double>(p.memory_bytes)) +
                                      " is too small for this store: the field of one slab (" +
                                      std::to_string(points.size()) + " points with its halo) takes " +
                                      budget_mib(static_cast<double>(fst.memory_bytes)) + "; it needs about --memory " +
                                      budget_mib(1.1 * (static_cast<double>(fst.memory_bytes) + others) + static_cast<double>(p.memory_bytes) - budget));
            }
            if (coverage) {
                coverage->set_value_range(plan.value_range);
                coverage->set_part_of(region.loaded);
            }
            if (!q.run(k0, k1, *field, coverage.get())) {  // the support test read past the loaded z range
                halo *= 2;
                ++rep.retries;
                continue;
            }
            cache.advance();
            add_slab_field_stats(rep.field, fst);
            rep.halo = std::max(rep.halo, halo);
            ++rep.slabs;
            break;
        }
        k0 = k1;
    }
    rep.reused_fits += cache.hits();
}


void print_store_query_stats(std::FILE* out, const char* cmd, const ScatteredStorePlan& plan, const StoreQueryReport& r) {
    std::fprintf(out,
                 "%s: point store in %d slabs (%d built again), halo up to %g world units, at most %llu of %llu points loaded at "
                 "once (%llu in all), %llu locals (%llu fits copied from the slab before, %llu regularised), largest slab field "
                 "%.1f MiB; time: plan %.3f s, read %.3f s, field %.3f s, queries %.3f s\n",
                 cmd, r.slabs, r.retries, r.halo, static_cast<unsigned long long>(r.most_loaded),
                 static_cast<unsigned long long>(plan.frame.points), static_cast<unsigned long long>(r.loaded),
                 static_cast<unsigned long long>(r.field.locals), static_cast<unsigned long long>(r.reused_fits),
                 static_cast<unsigned long long>(r.field.regularised), static_cast<double>(r.field.memory_bytes) / 1048576.0,
                 plan.seconds, r.read_seconds, r.field_seconds, r.query_seconds);
}

}  // namespace meshless
