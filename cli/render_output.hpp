// What the camera options of a command ask for (cli/common.hpp render_settings), and the file names
// of a turntable's frames (section 3.6: N frames, 360/N degrees apart about the y axis, written as
// NAME_000.png ...; stream/turntable.hpp draws them).
#pragma once
#include <string>

#include "kernels/splat_rasterizer.hpp"
#include "stream/splat_sink.hpp"

namespace meshless::cli {

struct RenderSettings {
    Camera camera;
    SplatKernel kernel = SplatKernel::ewa;
    ShadingParams shading;   ///< colours included (ShadingParams::color_by, colormap, value range)
    bool colorbar = false;   ///< draw the legend (kernels/colorbar.hpp): the value bar, or the block swatches
    std::uint32_t legend_blocks = 0;  ///< --color block: the number of blocks (0: unknown, all palette colours)
    /// EWA: bytes of footprints the splat sink keeps in memory (SplatSink::set_spool_memory); with
    /// --memory, which bounds the process (the brick cache), an eighth of it at most.
    std::size_t spool_memory = SplatSink::kSpoolMemory;
};

/// What --color asked for, before it is resolved against the input ("auto": value when the points'
/// values vary and the input is not an isosurface, else none).
enum class ColorRequest { automatic, value, block, normal, none };

/// The overlays the settings ask for, drawn into a rendered picture before it is written (with
/// rs.colorbar): the colour bar of the value range when colouring by value, the block swatches when
/// colouring by block.
void decorate_picture(const RenderSettings& rs, Image& img);

/// Frame i of a turntable goes to frame_path(path, i): "img.png" -> "img_007.png".
std::string frame_path(const std::string& path, int i);

}  // namespace meshless::cli
