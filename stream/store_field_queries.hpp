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
#include "stream/store_slab_runner.hpp"

namespace meshless {


/// A store opened for its queries, with its plan (plan_store_field: the frame, value range and the
/// cell counts the slabs read, on a grid of about 16 points a cell, at most 128 a side).
struct StoreQueries {
    std::unique_ptr<PointStore> store;
    ScatteredStorePlan plan;
};
StoreQueries open_store_queries(const std::string& path);


/// resample_field of the store's mpu field on grid `g` (resample_grid over the store's bounds) to
/// the float32 NRRD at `path`, slab by slab (see above); report (optional) gets the figures.
FieldQueryStats resample_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                     const GridSpec& g, const std::string& path, const FieldQueryRun& run,
                                     StoreQueryReport* report = nullptr);

/// The store's mpu field (value, and gradient when want_grad) at every position of `at`, in its
/// order, with the support test's figures: the positions taken in z order (stable), those of one z
/// in one slab (what probe writes; Python's Store.probe).
struct StorePositionValues {
    std::vector<double> value;
    std::vector<Vec3> grad;  ///< want_grad only
    FieldQueryStats stats;
};
StorePositionValues evaluate_store_positions(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                             const std::vector<Vec3>& at, bool want_grad, const FieldQueryRun& run,
                                             StoreQueryReport& report);

/// probe_field of the store's mpu field at `at`, in the given order, as CSV at `csv` ("-": stdout).
FieldQueryStats probe_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                                  std::vector<Vec3> at, const std::string& csv, const FieldQueryRun& run,
                                  StoreQueryReport* report = nullptr);

/// slice_field of the store's mpu field over `raster` (slice_raster over the store's bounds), the
/// store's points within req.near of the plane (default: half the mean spacing) drawn over it.
SliceResult slice_store_field(const PointStore& store, const ScatteredStorePlan& plan, const StoreQueryParams& p,
                              const PlaneRaster& raster, const SliceRequest& req, const FieldQueryRun& run,
                              StoreQueryReport* report = nullptr);


}  // namespace meshless
