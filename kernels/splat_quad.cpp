// Quadrilateral (QSplat-style) splat kernel of SplatFrame; see splat_rasterizer.hpp.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "kernels/shading.hpp"
#include "kernels/splat_rasterizer.hpp"

namespace meshless {

namespace {

// Exact ceil/floor of a float known to lie within +-2^30 (callers clamp): no libm call, no
// rounding-mode dependence (the x86-64 baseline has no roundss).
inline int iceil(float v) {
    const int i = static_cast<int>(v);
    return i + (static_cast<float>(i) < v);
}
inline int ifloor(float v) {
    const int i = static_cast<int>(v);
    return i - (static_cast<float>(i) > v);
}
inline float clamp_px(float v) { return std::clamp(v, -1e9f, 1e9f); }  // far outside any image, inside int

// The per-point loop, specialised on the projection so the inner work has no hoistable branch.
template <bool Perspective>
void draw_quad_points(const detail::FloatView& fv, const detail::Shader& shader, const ShadingParams& sh, int W, int H,
                      std::span<const PointRecord> points, std::span<const std::uint32_t> blocks, std::uint64_t* key,
                      std::int64_t& drawn, std::int64_t& frags) {
    const bool two_sided = sh.two_sided;
    const bool coloured = sh.color_by != ColorBy::none;
    for (std::size_t pi = 0; pi < points.size(); ++pi) {
        const PointRecord& rec = points[pi];
        if (!(std::isfinite(rec.pos[0]) && std::isfinite(rec.pos[1]) && std::isfinite(rec.pos[2]))) continue;
        float pc[3];
        fv.point(rec.pos, pc);
        const float depth = fv.distance - pc[2];
        if (!(depth > fv.near_depth)) continue;
        const float k = Perspective ? fv.focal / depth : fv.focal;
        const float sx = fv.cx + k * pc[0], sy = fv.cy - k * pc[1];
        const float r = std::isfinite(rec.radius) ? std::max(rec.radius, 0.0f) * k : 0.0f;
        // Pixels with centres in [s - r, s + r); at least the pixel under the centre.
        int x0 = iceil(clamp_px(sx - r - 0.5f)), x1 = iceil(clamp_px(sx + r - 0.5f)) - 1;
        int y0 = iceil(clamp_px(sy - r - 0.5f)), y1 = iceil(clamp_px(sy + r - 0.5f)) - 1;
        if (x1 < x0) x0 = x1 = ifloor(clamp_px(sx));
        if (y1 < y0) y0 = y1 = ifloor(clamp_px(sy));
        if (x1 < 0 || y1 < 0 || x0 > W - 1 || y0 > H - 1) continue;
        x0 = std::max(x0, 0);
        x1 = std::min(x1, W - 1);
        y0 = std::max(y0, 0);
        y1 = std::min(y1, H - 1);

        ++drawn;
        frags += static_cast<std::int64_t>(x1 - x0 + 1) * (y1 - y0 + 1);
        // Depth test before shading: a splat whose depth is beyond the stored depth of every pixel
        // it covers changes none of them (min of keys, depth in the high bits), so it is not shaded.
        const std::uint32_t depth_bits = std::bit_cast<std::uint32_t>(depth);
        bool reaches = false;
        for (int y = y0; y <= y1 && !reaches; ++y) {
            const std::uint64_t* row = key + static_cast<std::size_t>(y) * W;
            for (int x = x0; x <= x1; ++x) reaches |= static_cast<std::uint32_t>(row[x] >> 32) >= depth_bits;
        }
        if (!reaches) continue;
        float n[3], v[3];
        detail::oriented_normal(fv, rec, pc, depth, two_sided, n, v);
        std::uint32_t rgb;
        if (coloured) {
            const std::uint32_t c = splat_base_color(sh, rec, blocks, pi);
            const float colour[3] = {static_cast<float>(c >> 16) / 255.0f, static_cast<float>((c >> 8) & 255u) / 255.0f,
                                     static_cast<float>(c & 255u) / 255.0f};
            rgb = shader.shade(colour, n[0], n[1], n[2], v[0], v[1], v[2]);
        } else {
            rgb = shader.shade(n[0], n[1], n[2], v[0], v[1], v[2]);
        }
        const std::uint64_t kk = (static_cast<std::uint64_t>(depth_bits) << 32) | rgb;
        for (int y = y0; y <= y1; ++y) {
            std::uint64_t* row = key + static_cast<std::size_t>(y) * W;
            for (int x = x0; x <= x1; ++x) row[x] = std::min(row[x], kk);
        }
    }
}

}  // namespace

void SplatFrame::draw_quad(std::span<const PointRecord> points, std::uint64_t* key, SplatStats& st,
                           std::span<const std::uint32_t> blocks) const {
    const detail::FloatView fv(view_);
    const detail::Shader shader(shading_);
    std::int64_t drawn = 0, frags = 0;
    if (fv.perspective)
        draw_quad_points<true>(fv, shader, shading_, view_.width, view_.height, points, blocks, key, drawn, frags);
    else
        draw_quad_points<false>(fv, shader, shading_, view_.width, view_.height, points, blocks, key, drawn, frags);
    st.splats_drawn += drawn;
    st.fragments += frags;
}

void SplatFrame::resolve_quad(const std::uint64_t* key, Image& img) const {
    std::uint8_t* out = img.rgb.data();
    const auto& bg = shading_.background;
    const std::size_t n = npix();
    for (std::size_t i = 0; i < n; ++i, out += 3) {
        if (key[i] == kEmptyKey) {
            out[0] = bg[0];
            out[1] = bg[1];
            out[2] = bg[2];
        } else {
            detail::unpack_rgb(static_cast<std::uint32_t>(key[i] & 0xFFFFFFu), out);
        }
    }
}

}  // namespace meshless
