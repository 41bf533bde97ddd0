#include "stream/block_isosurface_job.hpp"

#include "formats/terminal_safe.hpp"
#include "stream/iso_range_warning.hpp"
#include "stream/seconds_since.hpp"

namespace meshless {

void warn_if_no_block_cell_crossed(std::FILE* out, const BlockIsosurfaceInput& in, double iso) {
    if (in.plan.active_cells == 0) warn_if_iso_outside(iso, in.plan.value_range, in.source, out);
    if (in.plan.active_cells == 0 && iso >= in.plan.value_range[0] && iso <= in.plan.value_range[1])
        std::fprintf(out, "meshless: warning: %s: no cell with valid corners is crossed by isovalue %g; the outputs will be empty\n",
                     terminal_safe(in.source).c_str(), iso);
}

std::size_t run_block_isosurface_job(const IsosurfaceJob& j, const BlockIsosurfaceInput& in, const IsosurfaceField& f,
                                     const char* cmd) {
    BlockIsosurfaceStats st;
    IsoSplatResult unused;
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t points = run_to_outputs(j.out, j.png, f.meta, j.rs, j.threads, [&](const Stage* draw, Sink& sink) {
        const auto g0 = std::chrono::steady_clock::now();
        if (!f.field.field) {
            st = run_block_isosurface(in, nullptr, j.iso, j.n, j.np, draw, sink, {j.threads});
        } else {
            // the blocks' cells as the source hands them out, counted ahead of seeding
            const auto progress = j.progress ? j.progress("cells", static_cast<double>(in.cells())) : std::function<void(double)>();
            st = run_block_isosurface(in, f.field.field.get(), j.iso, j.n, j.np, draw, sink, {j.threads}, progress);
        }
        IsoSplatResult r;
        r.seconds = seconds_since(g0);
        return r;
    }, unused, /*parallel_draw=*/true, /*with_blocks=*/true);
    const double graph_seconds = seconds_since(t0);
    if (j.stats)
        print_block_isosurface_stats(j.stats, cmd, in, st, j.n, f.name, j.np, points, {f.seconds, graph_seconds, seconds_since(j.started)},
                                     j.threads);
    return points;
}

}  // namespace meshless
