// How a splat picture is made (dissertation section 3.6): the camera, the kernel (quad or EWA),
// the shading and colouring, the legend, and the memory the EWA footprints may take; and the
// overlays drawn into a finished picture. Filled by the front ends from their options (the CLI's
// camera and colour options), read by the recipes that end in a picture. Does not throw.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "kernels/splat_rasterizer.hpp"
#include "stream/splat_sink.hpp"

namespace meshless {

/// The axes triad and scale bar (kernels/axes_overlay.hpp): drawn, not drawn, or drawn when the
/// world's length unit is known (the front ends' default: a bar labelled "50 mm" says something, one
/// of "50" in unknown units less).
enum class AxesChoice { off, on, when_unit_known };
/// Whether `choice` draws the axes for a world in `length_unit` ("" = unknown).
inline bool draws_axes(AxesChoice choice, const std::string& length_unit) {
    return choice == AxesChoice::on || (choice == AxesChoice::when_unit_known && !length_unit.empty());
}

struct RenderSettings {
    Camera camera;
    SplatKernel kernel = SplatKernel::ewa;
    ShadingParams shading;   ///< colours included (ShadingParams::color_by, colormap, value range)
    bool colorbar = false;   ///< draw the legend (kernels/colorbar.hpp): the value bar, or the block swatches
    std::uint32_t legend_blocks = 0;  ///< --color block: the number of blocks (0: unknown, all palette colours)
    std::string legend_title;  ///< the value bar's title: the name of the array the values are (empty: none)
    AxesChoice axes = AxesChoice::off;  ///< the axes triad and the scale bar (kernels/axes_overlay.hpp)
    std::string length_unit;   ///< the world's length unit (formats/length_unit.hpp; "": unknown): the scale bar's label
    /// EWA: bytes of footprints the splat sink keeps in memory (SplatSink::set_spool_memory); with
    /// --memory, which bounds the process (the brick cache), an eighth of it at most.
    std::size_t spool_memory = SplatSink::kSpoolMemory;
};

/// The overlays the settings ask for, drawn into a rendered picture before it is written (with
/// rs.colorbar): the colour bar of the value range when colouring by value, the block swatches when
/// colouring by block; when rs.axes draws them and given a view (the picture's camera over its
/// framed box), the axes triad and the scale bar labelled with rs.length_unit.
void decorate_picture(const RenderSettings& rs, Image& img, const ViewTransform* view = nullptr);

/// What a front end's colour option asked for, before it is resolved against the input ("auto":
/// value when the points' values vary and the input is not an isosurface, else none).
enum class ColorRequest { automatic, value, block, normal, none };

/// The colouring asked for: the request, the colour map, the value range (none: the data's) and
/// whether a legend is drawn.
struct ColorChoice {
    ColorRequest request = ColorRequest::automatic;
    Colormap colormap = Colormap::viridis;
    std::optional<std::array<double, 2>> range;
    bool colorbar = false;
};

/// The words of a front end's picture options (`--color`, `--kernel`, `--shading`): auto | value |
/// block | normal | none; quad | ewa; phong | lambert. InvalidArgument naming the option otherwise.
ColorRequest parse_color_request(const std::string& word);
SplatKernel parse_splat_kernel(const std::string& word);
ShadingParams parse_shading(const std::string& word);

/// The colouring a request asks for; `automatic` is what "auto" means for this input.
ColorBy color_by(const ColorChoice& c, ColorBy automatic);

/// The colours a point file carries (`--ply-color`, stream/point_file_sink.hpp): coloured `by`, with c's
/// colormap, over c's range, else over the recorded value range [value_min, value_max] of the points'
/// volume. Throws InvalidArgument (naming `source`) when `by` is value and neither range is known.
ShadingParams point_file_colors(ColorBy by, const ColorChoice& c, const std::optional<double>& value_min,
                                const std::optional<double>& value_max, const std::string& source);

/// Sets rs.shading's colouring (by, colormap, range) and rs.colorbar; `warn` (may be empty)
/// receives a one-line warning when a legend was asked for a picture coloured by neither value nor
/// block (none is drawn).
void apply_color(RenderSettings& rs, ColorBy by, const ColorChoice& c, const std::array<double, 2>& range,
                 const std::function<void(const std::string&)>& warn);

/// Frame i of a turntable (section 3.6: N frames, 360/N degrees apart about the up axis, drawn by
/// stream/turntable.hpp) goes to frame_path(path, i): "img.png" -> "img_007.png".
std::string frame_path(const std::string& path, int i);

}  // namespace meshless
