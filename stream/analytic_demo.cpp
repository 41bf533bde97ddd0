#include "stream/analytic_demo.hpp"

#include <filesystem>

#include "formats/terminal_safe.hpp"
#include "stream/point_outputs.hpp"
#include "stream/volume_input.hpp"

namespace meshless {

void run_analytic_demo(const AnalyticDemo& d, const std::string& dir, std::FILE* report) {
    VolumeInput in;
    in.path = std::string("demo-") + to_string(d.field);
    in.volume = make_analytic_volume(d.field, d.n);
    in.threads = d.threads;
    const double iso = default_iso(d.field);
    StreamMeta meta = volume_meta(in, iso, d.producer);  // value range and surface bounds
    meta.set("projection", "approx");
    RenderSettings rs = d.rs;
    // the surface is framed by 32-cell blocks; the torus and the sphere leave much of theirs empty
    if (!d.zoom_given && (d.field == AnalyticField::torus || d.field == AnalyticField::sphere)) rs.camera.zoom = 1.6;
    const int nthreads = in.threads;
    const std::string ply = (std::filesystem::path(dir) / "demo.ply").string(), png = (std::filesystem::path(dir) / "demo.png").string();
    IsoSplatResult r;
    const std::size_t points = run_to_outputs(GeometryOutput{ply, GeometryFormat::ply, {}, std::nullopt}, png, meta, rs, nthreads, [&](const Stage* draw, Sink& sink) {
        return run_isosplat_input(in, iso, Projection::approx, SamplingParams{}, sink, nthreads, PipelineShape::fused, {nullptr, draw});
    }, r);
    std::fprintf(report, "demo: %s field on a %lld^3 grid, iso %g: %zu points from %lld active cells in %.3f s\n"
                         "wrote %s and %s\n",
                 to_string(d.field), d.n, iso, points, static_cast<long long>(r.sampling.active_cells), r.seconds,
                 terminal_safe(ply).c_str(), terminal_safe(png).c_str());
}

}  // namespace meshless
