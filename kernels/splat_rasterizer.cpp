#include "kernels/splat_rasterizer.hpp"

#include <chrono>
#include <cmath>
#include <limits>

namespace meshless {

std::array<Vec3, 2> point_bounds(std::span<const PointRecord> points) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    for (const PointRecord& p : points) {
        if (!(std::isfinite(p.pos[0]) && std::isfinite(p.pos[1]) && std::isfinite(p.pos[2]))) continue;
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], static_cast<double>(p.pos[i]));
            hi[i] = std::max(hi[i], static_cast<double>(p.pos[i]));
        }
    }
    if (!(lo[0] <= hi[0])) return {Vec3{0, 0, 0}, Vec3{0, 0, 0}};
    return {Vec3{lo[0], lo[1], lo[2]}, Vec3{hi[0], hi[1], hi[2]}};
}

SplatRenderer::SplatRenderer(const Camera& cam, const ShadingParams& shading, const std::array<Vec3, 2>& bounds)
    : cam_(cam), shading_(shading), bounds_(bounds), view_(make_view(cam, bounds[0], bounds[1])) {}

void SplatRenderer::set_camera(const Camera& cam) {
    cam_ = cam;
    view_ = make_view(cam_, bounds_[0], bounds_[1]);
}

void SplatRenderer::set_bounds(const std::array<Vec3, 2>& bounds) {
    bounds_ = bounds;
    view_ = make_view(cam_, bounds_[0], bounds_[1]);
}

const Image& SplatRenderer::render(std::span<const PointRecord> points, SplatKernel kernel, SplatStats* stats) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t npix = static_cast<std::size_t>(cam_.width) * cam_.height;
    image_.width = cam_.width;
    image_.height = cam_.height;
    image_.rgb.resize(3 * npix);
    SplatStats st;
    if (kernel == SplatKernel::quad)
        render_quad(points, st);
    else
        render_ewa(points, st);
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (stats) *stats = st;
    return image_;
}

const Image& SplatRenderer::render(std::span<const PointRecord> points, SplatKernel kernel, double azimuth_deg,
                                   SplatStats* stats) {
    Camera c = cam_;
    c.azimuth_deg = azimuth_deg;
    set_camera(c);
    return render(points, kernel, stats);
}

Image render_splats(std::span<const PointRecord> points, const Camera& cam, SplatKernel kernel,
                    const ShadingParams& shading, SplatStats* stats, std::optional<std::array<Vec3, 2>> bounds) {
    SplatRenderer r(cam, shading, bounds ? *bounds : point_bounds(points));
    return r.render(points, kernel, stats);
}

}  // namespace meshless
