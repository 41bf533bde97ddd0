// A point store's MPU field (dissertation section 5.5) slab by slab along z within a memory budget,
// for the work that evaluates it in z order: the field queries (stream/store_field_queries.hpp) and
// the volume rendering (stream/store_render.hpp) of a `.mlc` (docs/architecture.md, "Fields out of
// core"; the pieces: stream/store_slab.hpp).
//
// The work is given as layers [0, count) in z order (rising, or falling when `descending`): a slab
// of layers [k0, k1) answers for z in range(k0, k1) over the x-y box given. Slabs are as many layers
// as the budget allows: the points they load cost other_bytes_per_point each, their field the most
// a point of a query range took so far (a slab's field holds the fits of the leaves meeting its
// query box, not of its halo; bytes_per_point a loaded point until a field is built), the work's
// own results bytes(k0, k1). Each slab loads its points, builds its field in the whole set's frame
// (and, with max_gap > 0, its support test with the whole set's value range, noting what it reads),
// builds again over the bricks its lacking balls meet until it is exact, takes fewer layers when
// the field does not fit, then calls run(k0, k1, field, coverage): false (the support test read
// beyond the loaded range) doubles the halo and runs the slab again. Both ways a run keeps the fits
// the next slab overlaps (kernels/mpu_fit_cache.hpp); a rising run also loads from a slab's first
// build the bricks that earlier lacking balls reach into it.
// Units: world, bytes. Throws InvalidArgument when the field is not mpu, or one layer's slab does
// not fit the budget (naming the budget that would do); FormatError/IoError from the store; what run throws.
#pragma once
#include <array>
#include <cstdint>
#include <cstdio>
#include <functional>

#include "formats/point_store.hpp"
#include "kernels/field_params.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/point_coverage.hpp"
#include "stream/scattered_store_isosurface.hpp"

namespace meshless {

/// The field, its support test and the budget of a store's slabs.
struct StoreQueryParams {
    FieldParams field;                        ///< an mpu field's (InvalidArgument otherwise)
    double max_gap = 1;                       ///< the support test's factor (0: none), as build_field's --max-gap
    Extrapolate extrapolate = Extrapolate::nan;
    std::uint64_t memory_bytes = 1ull << 30;  ///< the budget for a slab's points, field, support test and results
    double bytes_per_point = 1200;            ///< what one loaded point costs at first (field and the rest)
    /// What one loaded point costs beside its field: its record (32 bytes), its share of the octree's
    /// build lists and of the support test's tree, reach and values (10^8 LIDC2 samples, a slab of
    /// 2.07 M points: 881 MiB peak with a 507 MiB field, ~130 bytes a point beside it).
    double other_bytes_per_point = 160;
    double fixed_bytes = 0;                   ///< of the budget, what the work holds throughout (not the slabs')
                                              ///< beside the plan's cell table, which the slabs count themselves
};

/// What a slab run did (the --stats line).
struct StoreQueryReport {
    int slabs = 0;                  ///< slabs run
    int retries = 0;                ///< slab runs redone (lacking balls loaded, a wider halo, fewer layers)
    std::uint64_t most_loaded = 0;  ///< the most points loaded for one slab
    std::uint64_t loaded = 0;       ///< points loaded over all slabs (halos counted again)
    double halo = 0;                ///< the widest halo a slab needed, world units along z
    std::uint64_t reused_fits = 0;  ///< local fits copied from the slab before
    FieldBuildStats field;          ///< summed over the slabs' fields (locals of their query boxes)
    double read_seconds = 0, field_seconds = 0, query_seconds = 0;
};

/// The work in z order (see above).
struct SlabLayers {
    std::int64_t count = 0;
    bool descending = false;  ///< the layers' z falls with k
    /// The z range [lo, hi] (lo <= hi) the slab of layers [k0, k1) answers for.
    std::function<std::array<double, 2>(std::int64_t, std::int64_t)> range;
    /// The bytes the work's results of layers [k0, k1) hold while the slab runs.
    std::function<double(std::int64_t, std::int64_t)> bytes;
    /// The slab's work; false: the support test read beyond the loaded range (run again, wider).
    std::function<bool(std::int64_t, std::int64_t, const MpuField&, const PointCoverage*)> run;
};

/// Runs the layers slab by slab (see above) over the x-y extent `query_xy` (z ignored), building
/// on `threads` threads; rep gets the figures (added to what it holds).
void for_each_store_slab(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                         const std::array<Vec3, 2>& query_xy, const SlabLayers& layers, int threads, StoreQueryReport& rep);

/// The --stats line of a slab run ("CMD: point store in N slabs ..."), to `out`.
void print_store_query_stats(std::FILE* out, const char* cmd, const ScatteredStorePlan& plan, const StoreQueryReport& r);

}  // namespace meshless
