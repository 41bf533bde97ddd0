// meshless mc: standard marching cubes, the baseline of section 3.6 and the tests' reference surface.
#include <chrono>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "formats/ply_mesh.hpp"
#include "kernels/errors.hpp"
#include "kernels/marching_cubes.hpp"
#include "ooc/brick_marching_cubes.hpp"

namespace meshless::cli {

int cmd_mc(int argc, char** argv) {
    Args a("mc", "VOLUME --iso V -o mesh.ply",
           "Marching cubes (full 256-case table, shared vertices, gradient normals): the triangle-mesh\n"
           "baseline iso-splatting is compared against. Writes a binary PLY mesh. A brick store (.mlb) is\n"
           "triangulated brick by brick within --memory, seam vertices welded.");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "PLY mesh output (required; '-' = stdout)")
        .flag("stats", "print triangle/vertex counts, memory and timing to stderr");
    add_volume_options(a);
    add_memory_option(a);
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = parse_double(a.require("iso"), "--iso");
    const std::string out = a.require("output");
    VolumeInput in = open_volume_input(a);
    const std::string& path = in.path;
    warn_if_iso_outside(iso, in.value_range(), path);
    McStats st;
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh mesh = in.store ? marching_cubes_bricks(*in.store, *in.cache, *in.index, iso, &st)
                               : marching_cubes(in.volume->view(), iso, &st);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    write_ply_mesh(mesh, out);
    if (a.has("stats"))
        std::fprintf(stderr, "mc: %s iso %g: %lld active cells, %zu vertices, %zu triangles, %.1f MiB, %.3f s (%lld cells with NaN/Inf skipped)\n",
                     path.c_str(), iso, static_cast<long long>(st.active_cells), mesh.vertex_count(), mesh.triangle_count(),
                     mesh.memory_bytes() / 1048576.0, secs, static_cast<long long>(st.skipped_nonfinite));
    return 0;
}

}  // namespace meshless::cli
