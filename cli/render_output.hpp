// What the camera options of a command ask for (cli/common.hpp render_settings), and the file names
// of a turntable's frames (section 3.6: N frames, 360/N degrees apart about the y axis, written as
// NAME_000.png ...; stream/turntable.hpp draws them).
#pragma once
#include <string>

#include "kernels/splat_rasterizer.hpp"

namespace meshless::cli {

struct RenderSettings {
    Camera camera;
    SplatKernel kernel = SplatKernel::ewa;
    ShadingParams shading;
};

/// Frame i of a turntable goes to frame_path(path, i): "img.png" -> "img_007.png".
std::string frame_path(const std::string& path, int i);

}  // namespace meshless::cli
