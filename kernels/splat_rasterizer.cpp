#include "kernels/splat_rasterizer.hpp"

#include <chrono>
#include <cmath>
#include <algorithm>
#include <limits>

namespace meshless {

void PointBounds::add(std::span<const PointRecord> points) {
    // In float, without branches: a point with a non-finite coordinate offers +inf to the minima
    // and -inf to the maxima, which change nothing; min and max keep the first of equal values, as
    // the sequential double fold does (float -> double is exact and keeps the order), so the same
    // bounds, signed zeros included.
    constexpr float inf = std::numeric_limits<float>::infinity();
    float lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    for (const PointRecord& p : points) {
        const bool ok = std::isfinite(p.pos[0]) && std::isfinite(p.pos[1]) && std::isfinite(p.pos[2]);
        for (int i = 0; i < 3; ++i) {
            const float l = ok ? p.pos[i] : inf, h = ok ? p.pos[i] : -inf;
            lo[i] = l < lo[i] ? l : lo[i];
            hi[i] = hi[i] < h ? h : hi[i];
        }
    }
    for (int i = 0; i < 3; ++i) {
        lo_[i] = std::min(lo_[i], static_cast<double>(lo[i]));
        hi_[i] = std::max(hi_[i], static_cast<double>(hi[i]));
    }
}

void PointBounds::merge(const PointBounds& o) {
    for (int i = 0; i < 3; ++i) {
        lo_[i] = std::min(lo_[i], o.lo_[i]);
        hi_[i] = std::max(hi_[i], o.hi_[i]);
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

const Image& SplatRenderer::render(std::span<const PointRecord> points, SplatKernel kernel, SplatStats* stats,
                                   std::span<const std::uint32_t> blocks) {
    const auto t0 = std::chrono::steady_clock::now();
    const SplatFrame frame(cam_, kernel, shading_, bounds_);
    const std::size_t npix = frame.npix();
    SplatStats st;
    key_.assign(npix, SplatFrame::kEmptyKey);
    frame.draw(points, key_.data(), st, blocks);
    if (frame.two_pass()) {
        acc_.assign(frame.acc_words() * npix, 0);
        const VisibleDepthTiles tiles = frame.depth_tiles(key_.data());
        frame.accumulate(points, key_.data(), acc_.data(), st, blocks, &tiles);
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

std::uint32_t splat_base_color(const ShadingParams& sh, const PointRecord& p, std::span<const std::uint32_t> blocks,
                               std::size_t i) {
    std::array<std::uint8_t, 3> c = sh.base;
    switch (sh.color_by) {
        case ColorBy::none: break;
        case ColorBy::value: c = map_color(sh.colormap, p.value, sh.value_lo, sh.value_hi); break;
        case ColorBy::block: c = categorical_color(i < blocks.size() ? blocks[i] : 0); break;
        case ColorBy::normal: {
            const double n2 = double(p.normal[0]) * p.normal[0] + double(p.normal[1]) * p.normal[1] + double(p.normal[2]) * p.normal[2];
            if (!(n2 > 0) || !std::isfinite(n2)) {
                c = {128, 128, 128};
                break;
            }
            const double inv = 1 / std::sqrt(n2);
            for (int k = 0; k < 3; ++k)
                c[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::lround(std::clamp((p.normal[k] * inv + 1) * 127.5, 0.0, 255.0)));
            break;
        }
    }
    return (std::uint32_t{c[0]} << 16) | (std::uint32_t{c[1]} << 8) | c[2];
}

void SplatFrame::merge_keys(std::uint64_t* dst, const std::uint64_t* src, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) dst[i] = std::min(dst[i], src[i]);
}

void SplatFrame::merge_acc(std::int64_t* dst, const std::int64_t* src, std::size_t n) {
    constexpr std::size_t kRun = 512;
    for (std::size_t first = 0; first < n; first += kRun) {
        const std::size_t end = std::min(n, first + kRun);
        std::int64_t any = 0;
        for (std::size_t i = first; i < end; ++i) any |= src[i];
        if (any == 0) continue;
        for (std::size_t i = first; i < end; ++i) dst[i] += src[i];
    }
}

void SplatFrame::draw(std::span<const PointRecord> points, std::uint64_t* keys, SplatStats& stats,
                      std::span<const std::uint32_t> blocks) const {
    if (kernel_ == SplatKernel::quad) draw_quad(points, keys, stats, blocks);
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
                    const ShadingParams& shading, SplatStats* stats, std::optional<std::array<Vec3, 2>> bounds,
                    std::span<const std::uint32_t> blocks) {
    SplatRenderer r(cam, shading, bounds ? *bounds : point_bounds(points));
    return r.render(points, kernel, stats, blocks);
}

}  // namespace meshless
