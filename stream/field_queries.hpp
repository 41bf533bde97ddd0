// The field-query recipes of probe, slice and resample: the graphs that look at a meshless field
// directly (dissertation chapter 7, on the fields of chapters 4-5), one each (docs/architecture.md
// "Libraries"):
//   probe_field     given positions (QueryListSource) -> FieldEvaluateStage -> ProbeCsvSink
//                   ("x,y,z,value,gx,gy,gz")
//   slice_field     the pixel centres of an axis-aligned plane over the points' bounding box
//                   (PlaneRasterSource) -> FieldEvaluateStage -> SliceImageSink; then the data points
//                   near the plane drawn as 3x3 dots (white centre, dark rim) and the colour bar, PNG
//   resample_field  the samples of a regular grid over the points' bounding box (GridRasterSource)
//                   -> FieldEvaluateStage -> NrrdVolumeSink (float32)
// each with a ProgressStage after the evaluation that reports positions to the caller. The field's
// coverage (BuiltField, stream/field_data.hpp) masks positions outside the data and keeps values
// within the data's range (kernels/point_coverage.hpp). Outputs do not depend on the thread count.
// Units: world coordinates; the plane's pixel and the grid's spacing in world units.
// Throws IoError when an output cannot be written (nothing is left under its name), what the
// sources, stage and sinks throw (stream/field_sinks.hpp) otherwise.
#pragma once
#include <array>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "kernels/colormap.hpp"
#include "kernels/grid.hpp"
#include "kernels/point_set.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "stream/field_data.hpp"
#include "stream/field_query_sources.hpp"

namespace meshless {

/// What the evaluation did: positions evaluated, positions outside the data's support, values
/// moved into the data's range (FieldEvaluateStage).
struct FieldQueryStats {
    std::size_t positions = 0, uncovered = 0, clamped = 0;
};

/// What the evaluation found about the data's support (nothing when f has no coverage test): with
/// `stats`, how many positions lay outside the data and how many values were kept within its range;
/// and, under Extrapolate::nan (where no value outside is clamped), a warning when more than a tenth
/// of the values inside the data had to be clamped: the field overshoots its data there (sparse or
/// noisy values), and a picture's flat areas at the range's ends are the clamp's, not the data's.
/// Lines to `out`, naming `cmd`.
void report_field_support(std::FILE* out, const std::string& cmd, const BuiltField& f, const FieldQueryStats& e, bool stats);
/// The same for a field with (coverage) or without a support test, `mode` outside the data.
void report_field_support(std::FILE* out, const std::string& cmd, bool coverage, Extrapolate mode, const FieldQueryStats& e,
                          bool stats);

/// How a query graph runs.
struct FieldQueryRun {
    int threads = 1;  ///< workers (<= 0: available_cpus())
    std::function<void(double)> progress;  ///< positions evaluated (any thread; may be empty)
    /// Called once the field was evaluated, before slice_field draws and writes its picture (may be empty).
    std::function<void(const FieldQueryStats&)> evaluated;
};

/// The value and gradient of the field at each position, in order, as CSV at `csv` ("-": stdout).
FieldQueryStats probe_field(const BuiltField& f, std::vector<Vec3> at, const std::string& csv, const FieldQueryRun& run);

/// The raster of the plane `axis` = at over the points' bounding box: square pixels, the largest
/// that fit the box's extent in max_width x max_height (at least 2 x 2 pixels; a flat extent counts
/// as 1e-12).
PlaneRaster slice_raster(const PointSet& points, int axis, double at, int max_width, int max_height);
/// The same over the box {lo, hi}.
PlaneRaster slice_raster(const std::array<Vec3, 2>& box, int axis, double at, int max_width, int max_height);

/// The picture of slice_field.
struct SliceRequest {
    Colormap colormap = Colormap::coolwarm;
    std::array<double, 2> range{0, 1};  ///< the values at the colour map's ends
    std::optional<double> near;  ///< overlay points within this of the plane (default: half the mean point spacing)
    bool colorbar = false;       ///< draw the colour map and its range at the right edge
    std::string output;          ///< the PNG
};
struct SliceResult {
    FieldQueryStats queries;
    double near = 0;         ///< the overlay's distance to the plane
    std::size_t shown = 0;   ///< data points drawn
};
/// The field over `raster` colour-mapped (grey outside the data), the points within `near` of the
/// plane drawn over it, written as PNG.
SliceResult slice_field(const BuiltField& f, const PointSet& points, const PlaneRaster& raster, const SliceRequest& r,
                        const FieldQueryRun& run);

/// The overlay and the file of a slice whose field is in `img`: near_points within out.near of the
/// plane drawn as dots (out.shown counts them), the colour bar when asked, the PNG written.
void finish_slice(Image& img, const PointSet& near_points, const PlaneRaster& raster, const SliceRequest& r, SliceResult& out);

/// Half the mean point spacing of `points` points over `box`: its measure (over its non-flat axes)
/// per point, to the power one over their count (the slice's default overlay distance).
double half_spacing(const std::array<Vec3, 2>& box, std::size_t points);

/// The grid of `dims` samples spanning the points' bounding box (spacing 1 along an axis the box is flat in).
GridSpec resample_grid(const PointSet& points, const std::array<std::int64_t, 3>& dims);
/// The same over the box {lo, hi}.
GridSpec resample_grid(const std::array<Vec3, 2>& box, const std::array<std::int64_t, 3>& dims);
/// The NRRD comment of a resampled field: "meshless resample: FIELD field of N points".
inline std::string resample_comment(std::string_view field, std::uint64_t points) {
    return "meshless resample: " + std::string(field) + " field of " + std::to_string(points) + " points";
}
/// The field at the samples of `g`, x fastest, as a float32 NRRD at `path` whose comment names the
/// field and the points it was built from.
FieldQueryStats resample_field(const BuiltField& f, const PointSet& points, const GridSpec& g, const std::string& path,
                               const FieldQueryRun& run);

}  // namespace meshless
