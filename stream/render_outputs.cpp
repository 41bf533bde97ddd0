#include "stream/render_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "formats/png_writer.hpp"
#include "kernels/axes_overlay.hpp"
#include "kernels/colorbar.hpp"
#include "kernels/image_compare.hpp"
#include "stream/pipe_closure.hpp"

namespace meshless {

namespace {

std::string psnr_text(double psnr) {
    if (std::isinf(psnr)) return "inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", psnr);
    return buf;
}

}  // namespace

void write_render_files(const RenderInput& in, const Camera& cam, const RenderResult& rr, int threads, const RenderFiles& f) {
    // the legend and the axes drawn into the written picture (and so into the one compared)
    Image decorated;
    const std::string unit = in.volume ? in.volume->length_unit : std::string();
    // the legend titled with the array's name and the values' unit: "density (kg/m^3)", "HU"
    const std::string value_unit = in.volume ? in.volume->value_unit : std::string();
    const std::string title = value_unit.empty() ? f.legend_title
                              : f.legend_title.empty() ? value_unit
                                                       : f.legend_title + " (" + value_unit + ")";
    const bool axes = draws_axes(f.axes, unit);
    if (f.legend || axes) {
        decorated = rr.picture;
        if (f.legend) draw_transfer_legend(decorated, *f.legend, {255, 255, 255}, title);
        if (axes) draw_axes(decorated, make_view(cam, in.box[0], in.box[1]), {255, 255, 255}, unit);
    }
    const Image& picture = f.legend || axes ? decorated : rr.picture;
    const RayCastStats& st = rr.stats;
    // a closed stdout (-o - | head) still lets the difference picture be written; then the quiet exit
    PipeClosure pipe;
    const bool png_live = pipe.step([&] { write_png(picture, *f.png); });
    if (f.stats)
        std::fprintf(f.stats,
                     "render: %s, %dx%d, step %g (ref %g), %d thread(s): %.3f s; %llu rays hit, %llu samples (%.2f M/s), "
                     "%llu skipped as empty, %llu rays terminated early\n",
                     in.what.c_str(), cam.width, cam.height, rr.params.step, rr.params.ref_step, threads, rr.seconds,
                     static_cast<unsigned long long>(st.rays_hit), static_cast<unsigned long long>(st.samples),
                     1e-6 * static_cast<double>(st.samples) / std::max(rr.seconds, 1e-9), static_cast<unsigned long long>(st.skipped),
                     static_cast<unsigned long long>(st.terminated));
    if (f.reference) {
        const Image& ref = *f.reference;
        if (ref.width != picture.width || ref.height != picture.height)  // checked by the front end against its camera
            throw std::logic_error("render: the picture is not the size the camera asked for");
        const ImageDifference d = compare_images(picture, ref);
        std::fprintf(f.comparison, "RMSE %.4f PSNR %s dB (max difference %d, %llu of %llu pixels differ)\n",
                     d.rmse, psnr_text(d.psnr).c_str(), d.max_abs, static_cast<unsigned long long>(d.differing_pixels),
                     static_cast<unsigned long long>(picture.width) * static_cast<unsigned long long>(picture.height));
        if (f.diff)
            pipe.step([&] {
                write_png(difference_image(picture, ref, f.diff_gain), *f.diff);
                f.diff->commit();
            });
    }
    if (png_live) pipe.step([&] { f.png->commit(); });
    pipe.rethrow_if_closed();
}

}  // namespace meshless
