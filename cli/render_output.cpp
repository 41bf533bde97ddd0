#include "cli/render_output.hpp"

#include <algorithm>
#include <cstdio>

#include "formats/png_writer.hpp"

namespace meshless::cli {

SplatStats render_to_png(std::span<const PointRecord> pts, std::optional<std::array<Vec3, 2>> bounds,
                         const RenderSettings& rs, const std::string& png_path) {
    SplatStats st;
    const Image img = render_splats(pts, rs.camera, rs.kernel, rs.shading, &st, bounds);
    write_png(img, png_path);
    return st;
}

std::string frame_path(const std::string& path, int i) {
    char num[16];
    std::snprintf(num, sizeof num, "_%03d", i);
    const auto dot = path.rfind('.');
    const auto slash = path.rfind('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + num + ".png";
    return path.substr(0, dot) + num + path.substr(dot);
}

TurntableStats render_turntable(std::span<const PointRecord> pts, std::optional<std::array<Vec3, 2>> bounds,
                                const RenderSettings& rs, int frames, const std::string& png_path) {
    const Camera& cam = rs.camera;
    const SplatKernel kernel = rs.kernel;
    SplatRenderer r(cam, rs.shading, bounds ? *bounds : point_bounds(pts));
    TurntableStats t;
    t.frames = frames;
    double sum = 0;
    t.min_seconds = 1e300;
    for (int i = 0; i < frames; ++i) {
        SplatStats st;
        const Image& img = r.render(pts, kernel, cam.azimuth_deg + 360.0 * i / frames, &st);
        sum += st.seconds;
        t.min_seconds = std::min(t.min_seconds, st.seconds);
        t.max_seconds = std::max(t.max_seconds, st.seconds);
        write_png(img, frame_path(png_path, i));
    }
    t.mean_seconds = frames ? sum / frames : 0;
    if (!frames) t.min_seconds = 0;
    return t;
}

}  // namespace meshless::cli
