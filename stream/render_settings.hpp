// How a splat picture is made (dissertation section 3.6): the camera, the kernel (quad or EWA),
// the shading and colouring, the legend, and the memory the EWA footprints may take; and the
// overlays drawn into a finished picture. Filled by the front ends from their options (the CLI's
// camera and colour options), read by the recipes that end in a picture. Does not throw.
#pragma once
#include <cstdint>

#include "kernels/splat_rasterizer.hpp"
#include "stream/splat_sink.hpp"

namespace meshless {

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

/// The overlays the settings ask for, drawn into a rendered picture before it is written (with
/// rs.colorbar): the colour bar of the value range when colouring by value, the block swatches when
/// colouring by block.
void decorate_picture(const RenderSettings& rs, Image& img);

}  // namespace meshless
