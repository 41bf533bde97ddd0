// meshless mc: standard marching cubes, the baseline of section 3.6 and the tests' reference surface.
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "formats/ply_mesh.hpp"
#include "kernels/errors.hpp"
#include "stream/marching_cubes_stage.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/runner.hpp"

namespace meshless::cli {

int cmd_mc(int argc, char** argv) {
    Args a("mc", "VOLUME --iso V -o mesh.ply",
           "Marching cubes (full 256-case table, shared vertices, gradient normals): the triangle-mesh\n"
           "baseline iso-splatting is compared against. Writes a binary PLY mesh. Runs as a stage graph:\n"
           "z-slabs of the volume (or the active bricks of a brick store, .mlb, within --memory) are\n"
           "triangulated in parallel and welded along their shared edges: the mesh of one pass, the same\n"
           "bytes for any --threads.");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "PLY mesh output (required; '-' = stdout)")
        .flag("stats", "print triangle/vertex counts, memory and timing to stderr");
    add_volume_options(a);
    add_memory_option(a);
    add_thread_option(a);
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = parse_double(a.require("iso"), "--iso");
    const std::string out = require_output_extension(a.require("output"), ".ply", "-o", "a triangle mesh (binary PLY)");
    VolumeInput in = open_volume_input(a);
    const std::string& path = in.path;
    warn_if_iso_outside(iso, in.value_range(), path);
    const auto t0 = std::chrono::steady_clock::now();
    // source -> marching cubes -> welding PLY mesh writer
    std::unique_ptr<Source> source;
    std::unique_ptr<MarchingCubesStage> stage;
    if (in.store) {
        source = std::make_unique<McBrickSource>(in.index->active(iso));
        stage = std::make_unique<MarchingCubesStage>(*in.store, *in.cache, iso);
    } else {
        source = std::make_unique<McSlabSource>(in.volume->grid);
        stage = std::make_unique<MarchingCubesStage>(in.volume->view(), iso);
    }
    MeshWeldSink sink(out);
    const Stage* stages[] = {stage.get()};
    run_pipeline(*source, stages, sink, {threads(a)});
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const McStats st = stage->stats();
    const Mesh& mesh = sink.mesh();
    if (a.has("stats"))
        std::fprintf(stderr, "mc: %s iso %g: %lld active cells, %zu vertices, %zu triangles, %.1f MiB, %.3f s (%lld cells with NaN/Inf skipped)\n",
                     path.c_str(), iso, static_cast<long long>(st.active_cells), mesh.vertex_count(), mesh.triangle_count(),
                     mesh.memory_bytes() / 1048576.0, secs, static_cast<long long>(st.skipped_nonfinite));
    return 0;
}

}  // namespace meshless::cli
