#include "stream/field_queries.hpp"

#include <algorithm>
#include <cmath>

#include "formats/png_writer.hpp"
#include "kernels/colorbar.hpp"
#include "stream/field_evaluate_stage.hpp"
#include "stream/field_sinks.hpp"
#include "stream/progress_stage.hpp"
#include "stream/runner.hpp"

namespace meshless {

namespace {

/// source -> FieldEvaluateStage -> ProgressStage -> sink; then run.evaluated.
FieldQueryStats run_queries(Source& source, const BuiltField& f, Sink& sink, std::size_t positions, const FieldQueryRun& run) {
    const FieldEvaluateStage evaluate(*f.field, f.coverage.get(), f.extrapolate);
    const ProgressStage progress(run.progress);
    const Stage* stages[] = {&evaluate, &progress};
    run_pipeline(source, stages, sink, {run.threads});
    const FieldQueryStats s{positions, evaluate.uncovered(), evaluate.clamped()};
    if (run.evaluated) run.evaluated(s);
    return s;
}

/// The image axes of a plane normal to `axis`: the two others, x before y before z (u right, v up).
std::array<int, 2> image_axes(int axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    return {std::min(u, v), std::max(u, v)};
}

}  // namespace

double half_spacing(const std::array<Vec3, 2>& box, std::size_t points) {
    const auto [lo, hi] = box;
    const Vec3 ext = hi - lo;
    double vol = 1;
    int k = 0;
    for (int d = 0; d < 3; ++d)
        if (ext[d] > 0) vol *= ext[d], ++k;
    return 0.5 * (k ? std::pow(vol / static_cast<double>(std::max<std::size_t>(1, points)), 1.0 / k) : 0);
}

namespace {

/// Draws the points within `near` of the plane as 3x3 dots (white centre, dark rim); returns how many.
std::size_t draw_near_points(Image& img, const PointSet& points, const PlaneRaster& r, double near) {
    const auto [ua, va] = image_axes(r.axis);
    const int w = r.width, h = r.height;
    std::size_t shown = 0;
    for (const Vec3& p : points.pos) {
        if (std::abs(p[r.axis] - r.at) > near) continue;
        const int c = static_cast<int>((p[ua] - r.lo_u) / r.pixel), row = h - 1 - static_cast<int>((p[va] - r.lo_v) / r.pixel);
        ++shown;
        for (int dr = -1; dr <= 1; ++dr)
            for (int dc = -1; dc <= 1; ++dc) {
                const int rr = row + dr, cc = c + dc;
                if (rr < 0 || rr >= h || cc < 0 || cc >= w) continue;
                std::uint8_t* px8 = &img.rgb[3 * (static_cast<std::size_t>(rr) * w + cc)];
                px8[0] = px8[1] = px8[2] = (dr == 0 && dc == 0) ? 255 : 20;
            }
    }
    return shown;
}

}  // namespace

FieldQueryStats probe_field(const BuiltField& f, std::vector<Vec3> at, const std::string& csv, const FieldQueryRun& run) {
    const std::size_t positions = at.size();
    QueryListSource source(std::move(at), /*want_grad=*/true);
    ProbeCsvSink sink(csv);
    return run_queries(source, f, sink, positions, run);
}

PlaneRaster slice_raster(const PointSet& points, int axis, double at, int max_width, int max_height) {
    return slice_raster(points.bounds(), axis, at, max_width, max_height);
}

PlaneRaster slice_raster(const std::array<Vec3, 2>& box, int axis, double at, int max_width, int max_height) {
    const auto [lo, hi] = box;
    const auto [ua, va] = image_axes(axis);
    const double eu = std::max(hi[ua] - lo[ua], 1e-12), ev = std::max(hi[va] - lo[va], 1e-12);
    PlaneRaster r;
    r.axis = axis;
    r.at = at;
    r.lo_u = lo[ua];
    r.lo_v = lo[va];
    r.pixel = std::max(eu / max_width, ev / max_height);  // world units per pixel, aspect kept
    r.width = std::max(2, static_cast<int>(std::ceil(eu / r.pixel)));
    r.height = std::max(2, static_cast<int>(std::ceil(ev / r.pixel)));
    return r;
}

SliceResult slice_field(const BuiltField& f, const PointSet& points, const PlaneRaster& raster, const SliceRequest& r,
                        const FieldQueryRun& run) {
    PlaneRasterSource source(raster);
    SliceImageSink sink(raster.width, raster.height, r.colormap, r.range[0], r.range[1]);
    SliceResult out;
    out.queries = run_queries(source, f, sink, static_cast<std::size_t>(raster.width) * static_cast<std::size_t>(raster.height), run);
    out.near = r.near ? *r.near : half_spacing(points.bounds(), points.size());
    finish_slice(sink.image(), points, raster, r, out);
    return out;
}

void finish_slice(Image& img, const PointSet& near_points, const PlaneRaster& raster, const SliceRequest& r, SliceResult& out) {
    out.shown = draw_near_points(img, near_points, raster, out.near);
    if (r.colorbar) draw_colorbar(img, r.colormap, r.range[0], r.range[1]);
    write_png(img, r.output);
}

GridSpec resample_grid(const PointSet& points, const std::array<std::int64_t, 3>& dims) { return resample_grid(points.bounds(), dims); }

GridSpec resample_grid(const std::array<Vec3, 2>& box, const std::array<std::int64_t, 3>& dims) {
    const auto [lo, hi] = box;
    GridSpec g;
    for (int i = 0; i < 3; ++i) {
        g.dims[i] = dims[i];
        g.origin[i] = lo[i];
        g.spacing[i] = hi[i] > lo[i] ? (hi[i] - lo[i]) / static_cast<double>(dims[i] - 1) : 1.0;
    }
    return g;
}

FieldQueryStats resample_field(const BuiltField& f, const PointSet& points, const GridSpec& g, const std::string& path,
                               const FieldQueryRun& run) {
    GridRasterSource source(g);
    NrrdVolumeSink sink(g, path, resample_comment(f.field->name(), points.size()));
    return run_queries(source, f, sink, static_cast<std::size_t>(g.voxel_count()), run);
}

void report_field_support(std::FILE* out, const std::string& cmd, const BuiltField& f, const FieldQueryStats& e, bool stats) {
    report_field_support(out, cmd, f.coverage != nullptr, f.extrapolate, e, stats);
}

void report_field_support(std::FILE* out, const std::string& cmd, bool coverage, Extrapolate mode, const FieldQueryStats& e,
                          bool stats) {
    if (!coverage) return;
    static constexpr const char* kModes[] = {"NaN", "clamped", "the nearest data value"};
    if (stats)
        std::fprintf(out, "%s: %zu positions outside the data (%s), %zu values kept within the data range\n",
                     cmd.c_str(), e.uncovered, kModes[static_cast<int>(mode)], e.clamped);
    // (under --extrapolate nan, the default, only positions inside the data are clamped)
    const std::size_t inside = e.positions - std::min(e.positions, e.uncovered);
    if (mode == Extrapolate::nan && inside > 0 && 10 * e.clamped > inside)
        std::fprintf(out,
                     "meshless %s: warning: %zu of the %zu values inside the data (%.0f %%) lay outside its value range "
                     "and were clamped to it: the field overshoots its data there\n",
                     cmd.c_str(), e.clamped, inside, 100.0 * static_cast<double>(e.clamped) / static_cast<double>(inside));
}

}  // namespace meshless
