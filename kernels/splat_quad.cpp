// Quadrilateral (QSplat-style) splat kernel of SplatFrame; see splat_rasterizer.hpp.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "kernels/shading.hpp"
#include "kernels/splat_rasterizer.hpp"

namespace meshless {

void SplatFrame::draw_quad(std::span<const PointRecord> points, std::uint64_t* key, SplatStats& st) const {
    const int W = view_.width, H = view_.height;
    const detail::FloatView fv(view_);
    const detail::Shader shader(shading_);
    const bool two_sided = shading_.two_sided;
    const float Wm1 = float(W - 1), Hm1 = float(H - 1);
    std::int64_t drawn = 0, frags = 0;

    for (const PointRecord& rec : points) {
        if (!(std::isfinite(rec.pos[0]) && std::isfinite(rec.pos[1]) && std::isfinite(rec.pos[2]))) continue;
        float pc[3];
        fv.point(rec.pos, pc);
        const float depth = fv.distance - pc[2];
        if (!(depth > fv.near_depth)) continue;
        const float k = fv.perspective ? fv.focal / depth : fv.focal;
        const float sx = fv.cx + k * pc[0], sy = fv.cy - k * pc[1];
        const float r = std::isfinite(rec.radius) ? std::max(rec.radius, 0.0f) * k : 0.0f;
        // Pixels with centres in [s - r, s + r); at least the pixel under the centre.
        float fx0 = std::ceil(sx - r - 0.5f), fx1 = std::ceil(sx + r - 0.5f) - 1.0f;
        float fy0 = std::ceil(sy - r - 0.5f), fy1 = std::ceil(sy + r - 0.5f) - 1.0f;
        if (fx1 < fx0) fx0 = fx1 = std::floor(sx);
        if (fy1 < fy0) fy0 = fy1 = std::floor(sy);
        if (fx1 < 0 || fy1 < 0 || fx0 > Wm1 || fy0 > Hm1) continue;
        const int x0 = static_cast<int>(std::max(fx0, 0.0f)), x1 = static_cast<int>(std::min(fx1, Wm1));
        const int y0 = static_cast<int>(std::max(fy0, 0.0f)), y1 = static_cast<int>(std::min(fy1, Hm1));

        float n[3], v[3];
        detail::oriented_normal(fv, rec, pc, depth, two_sided, n, v);
        const std::uint64_t kk = (static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(depth)) << 32) |
                                 shader.shade(n[0], n[1], n[2], v[0], v[1], v[2]);
        ++drawn;
        frags += static_cast<std::int64_t>(x1 - x0 + 1) * (y1 - y0 + 1);
        for (int y = y0; y <= y1; ++y) {
            std::uint64_t* row = key + static_cast<std::size_t>(y) * W;
            for (int x = x0; x <= x1; ++x) row[x] = std::min(row[x], kk);
        }
    }
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
