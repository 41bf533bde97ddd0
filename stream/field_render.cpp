#include "stream/field_render.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "formats/transfer_function_file.hpp"
#include "kernels/block_minmax.hpp"
#include "kernels/errors.hpp"
#include "kernels/merge_near_duplicates.hpp"
#include "kernels/trilinear_field.hpp"
#include "ooc/brick_field.hpp"

namespace meshless {

namespace {
/// Edge, in cells, of the empty-space boxes of a volume in memory (a store uses its bricks).
constexpr int kVolumeMacroCells = 8;
}  // namespace

RenderInput volume_render_input(VolumeInput volume) {
    RenderInput in;
    in.volume = std::move(volume);
    const GridSpec& g = in.volume->grid();
    if (in.volume->store) {
        in.owned = std::make_unique<BrickStoreField>(*in.volume->store, *in.volume->cache);
        in.skip = store_value_bounds(*in.volume->store);
        const auto& info = in.volume->store->info();
        in.range = {info.value_min, info.value_max};
        in.what = "brick store, trilinear";
    } else {
        const VolumeView v = in.volume->volume->view();
        in.owned = std::make_unique<TrilinearField>(v);
        const BlockMinMax b = block_minmax(v, kVolumeMacroCells);
        in.range = b.range();
        in.skip = value_bounds_from_blocks(b, g);
        in.what = "volume, trilinear";
    }
    in.field = in.owned.get();
    in.box = in.field->bounds();
    in.spacing = std::min({g.spacing[0], g.spacing[1], g.spacing[2]});
    in.what += " " + std::to_string(g.dims[0]) + "x" + std::to_string(g.dims[1]) + "x" + std::to_string(g.dims[2]);
    return in;
}

RenderInput points_render_input(const PointSet& pts, const Field& field, const std::string& name) {
    if (pts.size() == 0) throw FormatError(name + ": no points to render");
    RenderInput in;
    in.field = &field;
    in.box = pts.bounds();
    in.range = pts.value_range();
    in.spacing = mean_point_spacing(pts.pos);
    if (!(in.spacing > 0)) throw FormatError(name + ": all points coincide; nothing to render");
    const double margin = kPointMargin * (in.range[1] - in.range[0]);
    in.skip = value_bounds_from_points(pts.pos, pts.value, in.box, kPointMacroCell * in.spacing, kPointPad * in.spacing, margin);
    in.what = std::to_string(pts.size()) + " points, " + field.name() + " field";
    return in;
}

std::array<Vec3, 2> render_frame(RenderInput& in, const std::optional<std::array<Vec3, 2>>& bounds) {
    if (!bounds) return in.box;
    const std::array<Vec3, 2> frame = *bounds;
    if (in.volume) {  // a grid has no values beyond its samples: render the part of the box it covers
        double lo[3], hi[3];
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::max(in.box[0][i], frame[0][i]);
            hi[i] = std::min(in.box[1][i], frame[1][i]);
        }
        in.box = {Vec3{lo[0], lo[1], lo[2]}, Vec3{hi[0], hi[1], hi[2]}};
    } else {
        in.box = frame;  // the field extrapolates beyond its points
    }
    return frame;
}

RayCastParams render_params(const RenderInput& in, const RenderOptions& o) {
    RayCastParams rp;
    rp.shade = o.shade;
    rp.background = o.background;
    rp.ref_step = o.ref_step ? *o.ref_step : 0.5 * in.spacing;
    rp.step = o.step ? *o.step : 0.5 * in.spacing;
    // a volume's trilinear gradient jumps at every cell face: shade with central differences over
    // one voxel (the same for the volume and its brick store, whose values are the same)
    if (in.volume) {
        const GridSpec& g = in.volume->grid();
        rp.gradient_step = {g.spacing[0], g.spacing[1], g.spacing[2]};
    }
    return rp;
}

ViewTransform render_view(RenderInput& in, const Camera& cam, const RenderOptions& o) {
    const std::array<Vec3, 2> frame = render_frame(in, o.bounds);
    if (o.no_skip && in.skip) {
        // every box with data becomes "unknown" (evaluated); boxes without data (scattered points that do
        // not reach them: kernels/value_bounds_grid.hpp) stay outside the picture, as with skipping
        for (std::size_t c = 0; c < in.skip->vmin.size(); ++c)
            if (!(in.skip->vmin[c] > in.skip->vmax[c])) in.skip->vmin[c] = in.skip->vmax[c] = std::nan("");
    }
    return make_view(cam, frame[0], frame[1]);
}

RenderResult render_field(RenderInput& in, const Camera& cam, const TransferFunction& tf, const RenderOptions& o,
                          const std::function<void(double)>& progress) {
    RenderResult r;
    r.params = render_params(in, o);
    const RayCastParams& rp = r.params;
    const ViewTransform view = render_view(in, cam, o);
    const auto t0 = std::chrono::steady_clock::now();
    const RgbaImage rgba = ray_cast_rgba(*in.field, in.box, view, tf, rp, in.skip ? &*in.skip : nullptr, o.threads,
                                         &r.stats, progress);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.picture = compose_over_background(rgba, rp.background);
    return r;
}

TransferFunction render_transfer_function(const std::string& name, std::array<double, 2> range, bool range_given) {
    if (is_transfer_function_preset(name)) {
        if (!(range[0] < range[1])) range = {range[0], range[0] + 1};  // constant data
        if (!std::isfinite(range[0]) || !std::isfinite(range[1])) range = {0, 1};
        return transfer_function_preset(name, range[0], range[1]);
    }
    if (range_given) throw InvalidArgument("--range applies to the transfer-function presets; " + name + " gives its own values");
    std::error_code ec;
    if (!std::filesystem::exists(name, ec)) {
        std::string names;
        for (auto n : transfer_function_preset_names()) names += (names.empty() ? "" : ", ") + std::string(n);
        throw InvalidArgument("--tf " + name + ": neither a preset (" + names + ") nor an existing file of 'value r g b a' rows");
    }
    return read_transfer_function_file(name);
}

}  // namespace meshless
