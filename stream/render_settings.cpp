#include "stream/render_settings.hpp"

#include "kernels/colorbar.hpp"

namespace meshless {

void decorate_picture(const RenderSettings& rs, Image& img) {
    if (rs.colorbar && rs.shading.color_by == ColorBy::value)
        draw_colorbar(img, rs.shading.colormap, rs.shading.value_lo, rs.shading.value_hi);
    if (rs.colorbar && rs.shading.color_by == ColorBy::block) draw_block_legend(img, rs.legend_blocks);
}

}  // namespace meshless
