#include "kernels/splat_rasterizer.hpp"

#include <chrono>
#include <cmath>
#include <algorithm>
#include <limits>

namespace meshless {

void PointBounds::add(std::span<const PointRecord> points) {
    for (const PointRecord& p : points) {
        if (!(std::isfinite(p.pos[0]) && std::isfinite(p.pos[1]) && std::isfinite(p.pos[2]))) continue;
        for (int i = 0; i < 3; ++i) {
            lo_[i] = std::min(lo_[i], static_cast<double>(p.pos[i]));
            hi_[i] = std::max(hi_[i], static_cast<double>(p.pos[i]));
        }
    }
}

std::array<Vec3, 2> PointBounds::bounds() const {
    if (!(lo_[0] <= hi_[0])) return {Vec3{0, 0, 0}, Vec3{0, 0, 0}};
    return {Vec3{lo_[0], lo_[1], lo_[2]}, Vec3{hi_[0], hi_[1], hi_[2]}};
}

std::array<Vec3, 2> point_bounds(std::span<const PointRecord> points) {
    PointBounds b;
    b.add(points);
    return b.bounds();
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
    const SplatFrame frame(cam_, kernel, shading_, bounds_);
    const std::size_t npix = frame.npix();
    SplatStats st;
    key_.assign(npix, SplatFrame::kEmptyKey);
    frame.draw(points, key_.data(), st);
    if (frame.two_pass()) {
        acc_.assign(4 * npix, 0);
        frame.accumulate(points, key_.data(), acc_.data(), st);
    }
    frame.resolve(key_.data(), acc_.data(), image_);
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (stats) *stats = st;
    return image_;
}

SplatFrame::SplatFrame(const Camera& cam, SplatKernel kernel, const ShadingParams& shading,
                       const std::array<Vec3, 2>& bounds)
    : view_(make_view(cam, bounds[0], bounds[1])), shading_(shading), kernel_(kernel) {
    if (kernel_ == SplatKernel::ewa) init_ewa();
}

void SplatFrame::merge_keys(std::uint64_t* dst, const std::uint64_t* src, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) dst[i] = std::min(dst[i], src[i]);
}

void SplatFrame::merge_acc(std::int64_t* dst, const std::int64_t* src, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) dst[i] += src[i];
}

void SplatFrame::draw(std::span<const PointRecord> points, std::uint64_t* keys, SplatStats& stats) const {
    if (kernel_ == SplatKernel::quad) draw_quad(points, keys, stats);
    else draw_ewa(points, keys, stats);
}

void SplatFrame::resolve(const std::uint64_t* keys, const std::int64_t* acc, Image& img) const {
    img.width = view_.width;
    img.height = view_.height;
    img.rgb.resize(3 * npix());
    if (kernel_ == SplatKernel::quad) resolve_quad(keys, img);
    else resolve_ewa(acc, img);
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
