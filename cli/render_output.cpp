#include "cli/render_output.hpp"

#include <cstdio>

#include "kernels/colorbar.hpp"

namespace meshless::cli {

std::string frame_path(const std::string& path, int i) {
    char num[16];
    std::snprintf(num, sizeof num, "_%03d", i);
    const auto dot = path.rfind('.');
    const auto slash = path.rfind('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + num + ".png";
    return path.substr(0, dot) + num + path.substr(dot);
}

void decorate_picture(const RenderSettings& rs, Image& img) {
    if (rs.colorbar && rs.shading.color_by == ColorBy::value)
        draw_colorbar(img, rs.shading.colormap, rs.shading.value_lo, rs.shading.value_hi);
    if (rs.colorbar && rs.shading.color_by == ColorBy::block) draw_block_legend(img, rs.legend_blocks);
}

}  // namespace meshless::cli
