// Marching cubes of a volume input (the section-3.6 baseline, `meshless mc`), the graph of
// stream/marching_cubes_stage.hpp over any kind of stream/volume_input.hpp input: a volume in memory
// in z-slabs, or the active bricks of a brick store through its cache. Memory: a store's cache plus
// the welded mesh in the sink. Throws what the store and the sink throw; the mesh does not depend on
// the thread count.
#pragma once
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "stream/marching_cubes_stage.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/volume_input.hpp"

namespace meshless {

/// The work units the graph hands out for `iso` (for a progress line): the active bricks of a
/// store, else the volume's cell layers.
double marching_cubes_work(const VolumeInput& in, double iso);

/// Runs marching cubes of `in` at `iso` into `sink` (normally a MeshWeldSink) on `threads`
/// threads; `progress` (may be empty) receives work units (marching_cubes_work) as they are done,
/// from any thread. Not for a slab-streamed input (open it with stream = false).
McStats run_marching_cubes(VolumeInput& in, double iso, Sink& sink, int threads,
                           const std::function<void(double)>& progress = {});

/// One surface of a run of several isovalues: its statistics and what it added to the mesh.
struct McSurface {
    McStats stats;
    std::size_t vertices = 0, triangles = 0;
};

/// Marching cubes of `in` at each of `isos` in turn into one mesh (`meshless mc --iso V1,V2,...`):
/// the surfaces appended in the order given, each welded on its own (MeshWeldSink::end_surface: no
/// vertex is shared between two surfaces), the sink finished once after the last. Per surface, as
/// run_marching_cubes; `progress` receives the work units of every surface.
std::vector<McSurface> run_marching_cubes(VolumeInput& in, const std::vector<double>& isos, MeshWeldSink& sink, int threads,
                                          const std::function<void(double)>& progress = {});

/// The statistics line of one run (prefixed `mc: `) to `out`: the active cells, the mesh's size
/// (`vertices`, `triangles`, `bytes` of memory), the time (seconds) and the cells skipped for a NaN/Inf corner.
void print_marching_cubes_stats(std::FILE* out, const std::string& path, double iso, const McStats& st, std::size_t vertices,
                                std::size_t triangles, std::size_t bytes, double seconds);

}  // namespace meshless
