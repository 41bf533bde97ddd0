#include "stream/volume_marching_cubes.hpp"

#include "formats/terminal_safe.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>

#include "stream/progress_stage.hpp"
#include "stream/runner.hpp"

namespace meshless {

double marching_cubes_work(const VolumeInput& in, double iso) {
    if (in.store) return static_cast<double>(in.index->active(iso).size());
    return static_cast<double>(std::max<std::int64_t>(0, in.grid().dims[2] - 1));
}

McStats run_marching_cubes(VolumeInput& in, double iso, Sink& sink, int threads, const std::function<void(double)>& progress) {
    if (!in.store && !in.volume) throw std::logic_error("run_marching_cubes: a slab-streamed input");
    // source -> marching cubes -> sink
    std::unique_ptr<Source> source;
    std::unique_ptr<MarchingCubesStage> stage;
    if (in.store) {
        source = std::make_unique<McBrickSource>(in.index->active(iso));
        stage = std::make_unique<MarchingCubesStage>(*in.store, *in.cache, iso);
    } else {
        source = std::make_unique<McSlabSource>(in.volume->grid);
        stage = std::make_unique<MarchingCubesStage>(in.volume->view(), iso);
    }
    // the work as the source hands it out: active bricks, or cell layers of the volume in memory
    const ProgressStage counter(progress, work_units);
    const Stage* stages[] = {&counter, stage.get()};
    run_pipeline(*source, stages, sink, {threads});
    return stage->stats();
}

namespace {
/// Hands the pieces of one surface to the mesh and, at the surface's end, starts the next one
/// (MeshWeldSink::end_surface) instead of writing the mesh.
class SurfaceSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::mesh; }
    explicit SurfaceSink(MeshWeldSink& mesh) : mesh_(mesh) {}
    void consume(Batch&& b) override { mesh_.consume(std::move(b)); }
    void finish() override { mesh_.end_surface(); }

private:
    MeshWeldSink& mesh_;
};
}  // namespace

std::vector<McSurface> run_marching_cubes(VolumeInput& in, const std::vector<double>& isos, MeshWeldSink& sink, int threads,
                                          const std::function<void(double)>& progress) {
    std::vector<McSurface> surfaces;
    SurfaceSink one(sink);
    for (double iso : isos) {
        const std::size_t v0 = sink.mesh().vertex_count(), t0 = sink.mesh().triangle_count();
        McSurface s;
        s.stats = run_marching_cubes(in, iso, one, threads, progress);
        s.vertices = sink.mesh().vertex_count() - v0;
        s.triangles = sink.mesh().triangle_count() - t0;
        surfaces.push_back(s);
    }
    sink.finish();
    return surfaces;
}

void print_marching_cubes_stats(std::FILE* out, const std::string& path, double iso, const McStats& st, std::size_t vertices,
                                std::size_t triangles, std::size_t bytes, double seconds) {
    std::fprintf(out, "mc: %s iso %g: %lld active cells, %zu vertices, %zu triangles, %.1f MiB, %.3f s (%lld cells with NaN/Inf skipped)\n",
                 terminal_safe(path).c_str(), iso, static_cast<long long>(st.active_cells), vertices, triangles,
                 bytes / 1048576.0, seconds, static_cast<long long>(st.skipped_nonfinite));
}

}  // namespace meshless
