// The field queries of a point store (.mlc, formats/point_store.hpp) within a memory budget:
// `meshless resample`, `probe` and `slice` of `pts.mlc` with the mpu field (dissertation section
// 5.5), run slab by slab along z (docs/architecture.md, "Fields out of core"; the pieces:
// stream/store_slab.hpp). The queries are taken in z order — a grid's layers, or the positions
// (the slice's pixels) sorted by z (stable) — and cut into slabs whose points (within a halo of the slab's z range) and
// field fit the budget; each slab's MPU field is built over its points in the whole set's frame and
// checked against the whole set's (lacking balls load their bricks and build again), its support
// test (kernels/point_coverage.hpp) over the same points keeps values within the whole set's range
// and is checked to have read only loaded neighbourhoods (else the halo doubles and the slab runs
// again). The evaluated batches of a slab go on to the sink in order once the slab is exact, so the
// output has the bytes of resample_field / probe_field over the whole store read into memory, for
// any budget and thread count. Fits overlapping the next slab are kept for it (kernels/mpu_fit_cache.hpp).
// Units: world coordinates, bytes. Memory: the budget holds a slab's points, field and support test
// (bytes_per_point until a field shows its own) and its evaluated batches; probe also holds the
// positions and their results (64 bytes each; a slice 32 bytes a pixel).
// Throws InvalidArgument when the field is not mpu, or the budget cannot hold one layer's (one
// position's) slab (the message says how much would); FormatError and IoError from the store
// (naming the file and the brick); IoError when the output cannot be written (nothing is left).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "formats/point_store.hpp"
#include "kernels/field_params.hpp"
#include "kernels/grid.hpp"
#include "kernels/point_coverage.hpp"
#include "stream/field_queries.hpp"
#include "stream/scattered_store_isosurface.hpp"

namespace meshless {

/// The field, its support test and the budget of a store's queries.
struct StoreQueryParams {
    FieldParams field;                        ///< an mpu field's (InvalidArgument otherwise)
    double max_gap = 1;                       ///< the support test's factor (0: none), as build_field's --max-gap
    Extrapolate extrapolate = Extrapolate::nan;
    std::uint64_t memory_bytes = 1ull << 30;  ///< the budget for a slab's points, field, support test and results
    double bytes_per_point = 1200;            ///< what one loaded point costs at first (field and the rest)
    double other_bytes_per_point = 320;       ///< what one loaded point costs beside its field
};

/// A store opened for its queries, with its plan (plan_scattered_store with the default binning:
/// the frame, value range and cell counts the slabs read).
struct StoreQueries {
    std::unique_ptr<PointStore> store;
    ScatteredStorePlan plan;
};
StoreQueries open_store_queries(const std::string& path);

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

/// resample_field of the store's mpu field on grid `g` (resample_grid over the store's bounds) to
/// the float32 NRRD at `path`, slab by slab (see above); report (optional) gets the figures.
FieldQueryStats resample_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                     const GridSpec& g, const std::string& path, const FieldQueryRun& run,
                                     StoreQueryReport* report = nullptr);

/// probe_field of the store's mpu field at `at`, in the given order, as CSV at `csv` ("-": stdout).
FieldQueryStats probe_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                  std::vector<Vec3> at, const std::string& csv, const FieldQueryRun& run,
                                  StoreQueryReport* report = nullptr);

/// slice_field of the store's mpu field over `raster` (slice_raster over the store's bounds), the
/// store's points within req.near of the plane (default: half the mean spacing) drawn over it.
SliceResult slice_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                              const PlaneRaster& raster, const SliceRequest& req, const FieldQueryRun& run,
                              StoreQueryReport* report = nullptr);

/// The --stats line of a slab run ("CMD: point store in N slabs ..."), to `out`.
void print_store_query_stats(std::FILE* out, const char* cmd, const ScatteredStorePlan& plan, const StoreQueryReport& r);

}  // namespace meshless
