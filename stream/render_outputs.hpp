// The files of a direct volume rendering (stream/field_render.hpp; dissertation section 6.6, Figure
// 6.6: LOD fields volume rendered and differenced against the original): the picture as a PNG, its
// statistics line, and against a reference picture the RMSE/PSNR line and the difference picture
// (|a - b| x gain, kernels/image_compare.hpp). When the picture goes to a standard output whose reader
// goes away (BrokenPipe), the difference picture is still written and committed, then BrokenPipe
// is rethrown (stream/pipe_closure.hpp). Throws what the PNG writer and AtomicFile throw; a reference
// of another size than the picture is a logic error (the front end checks it before rendering).
#pragma once
#include <cstdio>

#include "formats/atomic_file.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "stream/field_render.hpp"
#include "stream/render_settings.hpp"

namespace meshless {

struct RenderFiles {
    AtomicFile* png = nullptr;         ///< the picture (committed last)
    const Image* reference = nullptr;  ///< compared with the picture, when given
    AtomicFile* diff = nullptr;        ///< the difference picture (with a reference), when given
    double diff_gain = 1;
    std::FILE* comparison = stdout;    ///< where the RMSE/PSNR line goes
    std::FILE* stats = nullptr;        ///< where the statistics line goes (null: none)
    /// --colorbar: the transfer function's legend (kernels/colorbar.hpp draw_transfer_legend), titled
    /// legend_title (may be empty); null: none.
    const TransferFunction* legend = nullptr;
    std::string legend_title;
    /// The triad and the scale bar of the camera over the input's box (a volume's length unit, when
    /// its file says it, labels the bar and decides AxesChoice::when_unit_known).
    AxesChoice axes = AxesChoice::off;
};

/// Writes rr.picture of `in` (camera `cam`, `threads` ray-casting threads, for the statistics) to `f`.
void write_render_files(const RenderInput& in, const Camera& cam, const RenderResult& rr, int threads, const RenderFiles& f);

}  // namespace meshless
