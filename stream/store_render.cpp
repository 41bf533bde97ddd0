#include "stream/store_render.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "kernels/errors.hpp"
#include "kernels/merge_near_duplicates.hpp"
#include "kernels/ray_caster.hpp"
#include "stream/available_cpus.hpp"

namespace meshless {

RenderInput store_render_input(const StoreQueries& q, const std::string& name) {
    const ScatteredStorePlan& plan = q.plan;
    if (plan.frame.points == 0) throw FormatError(name + ": no points to render");
    RenderInput in;
    in.box = plan.frame.bounds;
    in.range = plan.value_range;
    in.spacing = mean_point_spacing(in.box, plan.frame.points);
    if (!(in.spacing > 0)) throw FormatError(name + ": all points coincide; nothing to render");
    // the empty-space boxes of every point, brick by brick (points_render_input's)
    ValueBoundsGrid skip = empty_point_bounds(in.box, kPointMacroCell * in.spacing);
    std::vector<double> raw;
    std::vector<Vec3> pos;
    std::vector<double> val;
    for (std::size_t i = 0; i < q.store->bricks().size(); ++i) {
        q.store->read_brick(i, raw);
        pos.resize(raw.size() / 4);
        val.resize(raw.size() / 4);
        for (std::size_t k = 0; k < pos.size(); ++k) {
            pos[k] = Vec3{raw[4 * k], raw[4 * k + 1], raw[4 * k + 2]};
            val[k] = raw[4 * k + 3];
        }
        add_point_bounds(skip, pos, val, kPointPad * in.spacing);
    }
    widen_point_bounds(skip, kPointMargin * (in.range[1] - in.range[0]));
    in.skip = std::move(skip);
    in.what = std::to_string(plan.frame.points) + " points, mpu field (a point store, in slabs)";
    return in;
}

RenderResult render_store_field(const StoreQueries& q, const StoreQueryParams& p, RenderInput& in, const Camera& cam,
                                const TransferFunction& tf, const RenderOptions& o, const std::function<void(double)>& progress,
                                StoreQueryReport* report) {
    RenderResult r;
    r.params = render_params(in, o);
    const ViewTransform view = render_view(in, cam, o);
    RayCastParts parts(in.box, view, tf, r.params, in.skip ? &*in.skip : nullptr);
    // the bands: the render box's z extent in as many as the binning grid has cell layers
    const auto bands = std::max<std::int64_t>(1, q.plan.grid.dims[2]);
    const double z0 = in.box[0].z, z1 = in.box[1].z;
    const auto edge = [&](std::int64_t b) { return b == bands ? z1 : z0 + (z1 - z0) * static_cast<double>(b) / static_cast<double>(bands); };
    const double pad = 1e-9 * std::max(1.0, std::abs(z0) + std::abs(z1));  // (a midpoint may round a hair beyond the box)
    const double inf = std::numeric_limits<double>::infinity();
    // the ray states and the empty-space boxes are held throughout
    StoreQueryParams sp = p;
    sp.max_gap = 0;
    const double fixed = 64.0 * static_cast<double>(view.width) * view.height + (in.skip ? 16.0 * static_cast<double>(in.skip->vmin.size()) : 0.0);
    sp.fixed_bytes += fixed;
    const int threads = o.threads > 0 ? o.threads : available_cpus();
    StoreQueryReport rep;
    const std::array<Vec3, 2> xy = {in.box[0] - Vec3{pad, pad, 0}, in.box[1] + Vec3{pad, pad, 0}};
    double done = 0;
    const double total = static_cast<double>(bands) * ((parts.pending(true) ? 1 : 0) + (parts.pending(false) ? 1 : 0));
    for (const bool rising : {true, false}) {
        if (!parts.pending(rising)) continue;
        // the bands [b0, b1) of layers [k0, k1): from the bottom when rising, from the top when falling
        const auto band_range = [&](std::int64_t k0, std::int64_t k1) {
            return rising ? std::array<std::int64_t, 2>{k0, k1} : std::array<std::int64_t, 2>{bands - k1, bands - k0};
        };
        SlabLayers layers;
        layers.count = bands;
        layers.descending = !rising;
        layers.range = [&](std::int64_t k0, std::int64_t k1) {
            const auto b = band_range(k0, k1);
            return std::array<double, 2>{edge(b[0]) - pad, edge(b[1]) + pad};
        };
        layers.bytes = [](std::int64_t, std::int64_t) { return 0.0; };
        layers.run = [&](std::int64_t k0, std::int64_t k1, const MpuField& field, const PointCoverage*) {
            const auto b = band_range(k0, k1);
            // samples in [edge(b0), edge(b1)), the lowest band from -infinity, the highest to +infinity
            const std::array<double, 2> z{b[0] == 0 ? -inf : edge(b[0]), b[1] == bands ? inf : edge(b[1])};
            const auto t1 = std::chrono::steady_clock::now();
            parts.advance(field, rising, z, b[1] == bands, threads);
            rep.query_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
            done += static_cast<double>(k1 - k0);
            if (progress && total > 0) progress(done / total);
            return true;
        };
        for_each_store_slab(*q.store, q.plan, sp, xy, layers, threads, rep);
    }
    r.stats = parts.stats();
    r.seconds = rep.query_seconds;  // the ray casting's (the slabs' fields: report)
    r.picture = compose_over_background(parts.image(), r.params.background);
    if (report) *report = rep;
    return r;
}

}  // namespace meshless
