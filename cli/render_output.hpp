// Rendering points to PNG files for the CLI: one frame, or a turntable (section 3.6: N frames,
// 360/N degrees apart about the y axis) written as NAME_000.png ... with the time per frame.
#pragma once
#include <optional>
#include <span>
#include <string>

#include "kernels/splat_rasterizer.hpp"

namespace meshless::cli {

/// Renders and writes one PNG (temporary name + rename). Bounds default to the points' bounds.
/// What the camera options of a command ask for (cli/common.hpp render_settings).
struct RenderSettings {
    Camera camera;
    SplatKernel kernel = SplatKernel::ewa;
    ShadingParams shading;
};

SplatStats render_to_png(std::span<const PointRecord> pts, std::optional<std::array<Vec3, 2>> bounds,
                         const RenderSettings& rs, const std::string& png_path);

/// Frame i of a turntable goes to frame_path(path, i): "img.png" -> "img_007.png".
std::string frame_path(const std::string& path, int i);

struct TurntableStats {
    int frames = 0;
    double mean_seconds = 0, min_seconds = 0, max_seconds = 0;
};
TurntableStats render_turntable(std::span<const PointRecord> pts, std::optional<std::array<Vec3, 2>> bounds,
                                const RenderSettings& rs, int frames, const std::string& png_path);

}  // namespace meshless::cli
