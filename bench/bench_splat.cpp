// meshless-bench splat: software surface-splatting frame times (dissertation §3.6: frame rate over
// 36 frames, the model rotated 10 degrees about the y axis each time), quad and EWA kernels, for
// several point counts (every k-th point of one isosurface).
#include <filesystem>

#include "bench/bench_common.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"

namespace meshless::bench {

void run_splat(const BenchOptions& o, Report& r) {
    r.section("Splatting: software renderer frame times, 800x800 (dissertation 3.6)");
    namespace fs = std::filesystem;
    std::error_code ec;
    const std::string lidc = (fs::path(o.data_dir) / "vtkjs_LIDC2/LIDC2.vti").string();
    std::string label;
    Volume vol;
    double iso = 0;
    if (!o.quick && !o.data_dir.empty() && fs::exists(lidc, ec)) {
        vol = read_volume(lidc);
        const std::vector<double> isos = pick_isovalues(vol, 3);
        iso = isos.empty() ? 0 : isos[isos.size() / 2];
        label = fmt("LIDC2 chest CT iso %g", iso);
    } else {
        const std::int64_t n = o.quick ? 96 : 256;
        vol = make_analytic_volume(AnalyticField::sphere, n);
        iso = default_iso(AnalyticField::sphere);
        label = fmt("analytic sphere %lld^3 iso %g", static_cast<long long>(n), iso);
        r.note(o.quick ? "--quick: using an analytic sphere instead of the LIDC2 chest CT"
                       : "LIDC2 not found under the data folder: using an analytic sphere");
    }
    CollectSink sink;
    run_isosplat(vol.view(), iso, Projection::approx, SamplingParams{}, sink, RunOptions{1});
    const std::vector<PointRecord>& all = sink.points;
    const auto bounds = point_bounds(all);
    const int frames = o.quick ? 4 : 36;
    r.note(fmt("%s: %zu points (approximate projection). Camera: perspective, 800x800, elevation 20 deg; "
               "first frame (allocates buffers) and the mean over a %d-frame turntable (10 deg steps), single "
               "thread. Fewer points = every k-th point.",
               label.c_str(), all.size(), frames));
    Table t;
    t.header = {"points", "kernel", "first frame ms", "turntable ms/frame", "fps", "ms per Mpoints", "fragments/frame"};
    for (int step : {8, 4, 2, 1}) {
        std::vector<PointRecord> pts;
        pts.reserve(all.size() / step + 1);
        for (std::size_t i = 0; i < all.size(); i += static_cast<std::size_t>(step)) pts.push_back(all[i]);
        for (SplatKernel kernel : {SplatKernel::quad, SplatKernel::ewa}) {
            Camera cam;
            cam.width = cam.height = 800;
            SplatRenderer renderer(cam, ShadingParams{}, bounds);
            Stopwatch first;
            renderer.render(pts, kernel, 0.0);
            const double first_ms = first.ms();
            std::int64_t fragments = 0;
            Stopwatch sw;
            for (int f = 0; f < frames; ++f) {
                SplatStats st;
                renderer.render(pts, kernel, 10.0 * f, &st);
                fragments += st.fragments;
            }
            const double mean = sw.ms() / frames;
            t.add({fmt("%zu", pts.size()), kernel == SplatKernel::quad ? "quad" : "ewa", fmt("%.2f", first_ms),
                   fmt("%.2f", mean), mean > 0 ? fmt("%.1f", 1e3 / mean) : "-",
                   pts.empty() ? "-" : fmt("%.1f", mean / (static_cast<double>(pts.size()) / 1e6)),
                   fmt("%lld", static_cast<long long>(fragments / frames))});
        }
    }
    r.table(t);
}

}  // namespace meshless::bench
