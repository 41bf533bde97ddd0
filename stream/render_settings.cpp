#include "stream/render_settings.hpp"

#include <cstdio>

#include "kernels/axes_overlay.hpp"
#include "kernels/colorbar.hpp"
#include "kernels/errors.hpp"

namespace meshless {

void decorate_picture(const RenderSettings& rs, Image& img, const ViewTransform* view) {
    if (draws_axes(rs.axes, rs.length_unit) && view) draw_axes(img, *view, {255, 255, 255}, rs.length_unit);
    if (rs.colorbar && rs.shading.color_by == ColorBy::value)
        draw_colorbar(img, rs.shading.colormap, rs.shading.value_lo, rs.shading.value_hi, {255, 255, 255}, rs.legend_title);
    if (rs.colorbar && rs.shading.color_by == ColorBy::block) draw_block_legend(img, rs.legend_blocks);
}

ColorBy color_by(const ColorChoice& c, ColorBy automatic) {
    switch (c.request) {
        case ColorRequest::value: return ColorBy::value;
        case ColorRequest::block: return ColorBy::block;
        case ColorRequest::normal: return ColorBy::normal;
        case ColorRequest::none: return ColorBy::none;
        case ColorRequest::automatic: break;
    }
    return automatic;
}

ShadingParams point_file_colors(ColorBy by, const ColorChoice& c, const std::optional<double>& value_min,
                                const std::optional<double>& value_max, const std::string& source) {
    ShadingParams colors;
    colors.color_by = by;
    colors.colormap = c.colormap;
    if (c.range) {
        colors.value_lo = (*c.range)[0];
        colors.value_hi = (*c.range)[1];
    } else if (value_min && value_max) {
        colors.value_lo = *value_min;
        colors.value_hi = *value_max;
    } else if (by == ColorBy::value) {
        throw InvalidArgument("--ply-color value: " + source + " records no value range; give --range LO,HI");
    }
    return colors;
}

void apply_color(RenderSettings& rs, ColorBy by, const ColorChoice& c, const std::array<double, 2>& range,
                 const std::function<void(const std::string&)>& warn) {
    rs.shading.color_by = by;
    rs.shading.colormap = c.colormap;
    rs.shading.value_lo = range[0];
    rs.shading.value_hi = range[1];
    rs.colorbar = c.colorbar;
    if (c.colorbar && by != ColorBy::value && by != ColorBy::block && warn)
        warn("warning: --colorbar: the picture is coloured by neither value nor block; no legend drawn");
}

std::string frame_path(const std::string& path, int i) {
    char num[16];
    std::snprintf(num, sizeof num, "_%03d", i);
    const auto dot = path.rfind('.');
    const auto slash = path.rfind('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + num + ".png";
    return path.substr(0, dot) + num + path.substr(dot);
}

ColorRequest parse_color_request(const std::string& m) {
    if (m == "auto") return ColorRequest::automatic;
    if (m == "value") return ColorRequest::value;
    if (m == "block") return ColorRequest::block;
    if (m == "normal") return ColorRequest::normal;
    if (m == "none") return ColorRequest::none;
    throw InvalidArgument("--color: expected value, block, normal or none, got '" + m + "'");
}

SplatKernel parse_splat_kernel(const std::string& k) {
    if (k == "quad") return SplatKernel::quad;
    if (k == "ewa") return SplatKernel::ewa;
    throw InvalidArgument("--kernel: expected quad or ewa, got '" + k + "'");
}

ShadingParams parse_shading(const std::string& m) {
    ShadingParams s;
    if (m == "lambert") s.specular = 0;
    else if (m != "phong") throw InvalidArgument("--shading: expected phong or lambert, got '" + m + "'");
    return s;
}

}  // namespace meshless
