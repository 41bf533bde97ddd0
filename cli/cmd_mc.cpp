// meshless mc: standard marching cubes, the baseline of section 3.6 and the tests' reference
// surface; on multiblock inputs, the naive per-block marching cubes of section 4.2 (Figures
// 4.6-4.8) with its crack and intersection statistics.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/point_set_cli.hpp"
#include "cli/progress_meter.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/ply_mesh.hpp"
#include "kernels/errors.hpp"
#include "stream/naive_block_mc.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/volume_marching_cubes.hpp"
#include "stream/seconds_since.hpp"

namespace meshless::cli {

namespace {

/// The naive per-block marching cubes of a multiblock input (section 4.2).
int mc_blocks(const Args& a, double iso, const std::string& out, GeometryFormat format) {
    const auto t0 = std::chrono::steady_clock::now();
    const Multiblock mb = read_multiblock(a.positional(), point_set_options(a));
    const std::string& name = a.positional().size() == 1 ? a.positional()[0] : a.positional()[0] + " ...";
    const bool warned = warn_if_iso_outside(iso, multiblock_value_range(mb), name);
    const double read_s = seconds_since(t0);
    // census -> block cell layers -> per-block marching cubes -> welding PLY mesh writer (+ stats)
    const NaiveMcResult r = naive_block_marching_cubes(mb, iso, threads(a), out, a.has("stats"), format, vtp_options(a, threads(a)));
    if (a.has("stats")) print_naive_block_mc_stats(stderr, name, mb, iso, r, read_s);
    return empty_result_exit(a, r.mesh.triangle_count(), "triangles", iso, name, warned);
}

}  // namespace

int cmd_mc(int argc, char** argv) {
    Args a("mc", "VOLUME --iso V -o mesh.ply|mesh.vtp | BLOCKS... --iso V -o naive.ply [--stats]",
           "Marching cubes (full 256-case table, shared vertices, normals -grad f/|grad f| pointing to\n"
           "decreasing values and triangles counter-clockwise seen from the normal side, as VTK's: a closed\n"
           "surface around high values has positive signed volume): the triangle-mesh baseline\n"
           "iso-splatting is compared against. Writes a binary PLY mesh. Runs as a stage graph:\n"
           "z-slabs of the volume (or the active bricks of a brick store, .mlb, within --memory) are\n"
           "triangulated in parallel and welded along their shared edges: the mesh of one pass, the same\n"
           "bytes for any --threads. --memory bounds the bricks held, not the mesh: the welded mesh is held\n"
           "until it is written (a PLY or VTP mesh states its counts before its data): 24 bytes a vertex\n"
           "and 12 a triangle, and the keys of seam vertices; iso-splatting's points stream instead.\n"
           "BLOCKS (multiblock grids: .vts pieces, .vtm, .vthb, PLOT3D .xyz/.x/.bin/.p3d, several files =\n"
           "several blocks): the naive baseline of dissertation section 4.2 (Figures 4.6-4.8): plain\n"
           "marching cubes per block on the block's own trilinear interpolant, cell by cell in physical\n"
           "space; cells with an invalid (blanked/NaN) corner or a collapsed/inverted cell (corner\n"
           "Jacobians not all of one sign) are skipped and counted; each block is oriented by the sign of\n"
           "most of its cells' Jacobians. Vertices are welded within a block, never across blocks; the\n"
           "PLY and the .vtp carry per-vertex normals (area-weighted normals of the triangles around each\n"
           "vertex, which point toward decreasing value) and the block of each triangle (the block's index,\n"
           "inputs in order): a per-face 'uint block' property in the PLY, a per-cell 'block' array in the .vtp.\n"
           "--stats then also welds vertices across blocks by exact (float) position and reports:\n"
           "  boundary edges: edges of exactly one triangle;\n"
           "  crack edges: boundary edges whose midpoint lies inside a cell (all corners valid; 1e-3\n"
           "    parametric tolerance) of a block other than the edge's own, i.e. not on the outer boundary\n"
           "    of the data (the edge's own block is left out: its boundary edges lie on its own boundary);\n"
           "  intersecting pairs: triangles of different blocks that intersect beyond a shared vertex or\n"
           "    edge (CGAL box intersection + exact predicates); triangles of different blocks with the\n"
           "    same three vertices (overlapping blocks with coincident nodes) are counted apart as\n"
           "    duplicated pairs.");
    a.option("iso", "", "V[,V2...]", "isovalue (required); several, comma-separated: their surfaces in one mesh, in this order")
        .option("output", "o", "FILE", "mesh output (required): .ply binary PLY or .vtp VTK XML PolyData (polygons, Normals, per-cell 'block'); '-' = stdout")
        .flag("stats", "print counts and timing to stderr (BLOCKS: also crack edges and intersecting pairs)");
    add_fail_empty_option(a);
    add_geometry_format_option(a);
    add_volume_options(a);
    add_crop_option(a);
    add_point_set_options(a, false);
    add_memory_option(a);
    add_thread_option(a);
    add_quiet_option(a);
    a.positionals(1, 4096);
    a.epilog("examples: meshless mc vol.nrrd --iso 100.5 -o mesh.ply\n"
             "          meshless mc multicomb_0.vts multicomb_1.vts multicomb_2.vts --iso 0.4 -o naive.ply --stats\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string out = a.require("output");
    const GeometryFormat format = geometry_output_format(a, out, "a triangle mesh");
    if (a.positional().size() > 1 || looks_like_multiblock(a.positional()[0]))
        return mc_blocks(a, single_iso(a, "multiblock grids"), out, format);
    const std::vector<double> isos = isovalue_list(a);
    VolumeInput in = open_volume_input(a);
    const std::string& path = in.path;
    bool warned = false;
    for (double iso : isos) warned = warn_if_iso_outside(iso, in.value_range(), path, stderr, isos.size() > 1) || warned;
    const auto t0 = std::chrono::steady_clock::now();
    MeshWeldSink sink(out, format, vtp_options(a, threads(a)));
    double work = 0;
    for (double iso : isos) work += marching_cubes_work(in, iso);
    ProgressMeter meter = ProgressMeter::of(a, in.store ? "bricks" : "cell layers", work);
    const std::vector<McSurface> surfaces = run_marching_cubes(in, isos, sink, threads(a), [&](double n) { meter.add(n); });
    meter.done();
    const double secs = seconds_since(t0);
    if (a.has("stats"))
        for (std::size_t i = 0; i < isos.size(); ++i)
            print_marching_cubes_stats(stderr, path, isos[i], surfaces[i].stats, surfaces[i].vertices, surfaces[i].triangles,
                                       sink.mesh().memory_bytes(), secs);
    return empty_result_exit(a, sink.mesh().triangle_count(), "triangles", isos[0], path, warned);
}

}  // namespace meshless::cli
