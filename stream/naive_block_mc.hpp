// The naive per-block marching cubes of a multiblock grid and its statistics in one call (what
// `meshless mc BLOCKS... --stats` runs, and what a benchmark compares the meshless method against:
// dissertation section 4.2, Figures 4.6-4.8). The graph is stream/block_mc_stage.hpp's (census pass,
// then block cell layers -> per-block marching cubes -> welding sink, optionally writing the PLY);
// the statistics are kernels/crack_edges.hpp (crack edges: boundary edges after welding by exact
// position whose midpoint lies in a valid cell of another block, located by
// kernels/hex_point_location.hpp over the cells near the boundary) and
// kernels/triangle_pair_intersections.hpp (CGAL).
// Throws what the graph and the PLY writer throw. Not thread-safe (runs its own graph on `threads`).
#pragma once
#include <array>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "formats/geometry_format.hpp"
#include "formats/vtp_writer.hpp"
#include "kernels/crack_edges.hpp"
#include "kernels/triangle_pair_intersections.hpp"
#include "stream/block_mc_stage.hpp"

namespace meshless {

struct NaiveMcResult {
    Mesh mesh;                               ///< welded within blocks, Mesh::block per triangle
    BlockMcTotals totals;                    ///< cells, active, skipped
    std::vector<BlockOrientation> census;    ///< per block
    std::optional<CrackEdgeStats> cracks;    ///< with stats
    std::optional<TrianglePairStats> pairs;  ///< with stats
    double mc_seconds = 0, crack_seconds = 0, pair_seconds = 0;
};

/// ply_path: also write the mesh there (empty: no file), as `format` (PLY or VTP). stats: also the
/// crack and pair statistics.
NaiveMcResult naive_block_marching_cubes(const Multiblock& mb, double iso, int threads, const std::string& ply_path = {},
                                         bool stats = false, GeometryFormat format = GeometryFormat::ply, VtpOptions vtp = {});

/// The lowest and highest finite value of `mb`'s valid nodes ({+inf, -inf} when there is none).
std::array<double, 2> multiblock_value_range(const Multiblock& mb);

/// The statistics of one run (`meshless mc BLOCKS... --stats`) to `out`, each line prefixed `mc: `:
/// the cells and why some were skipped, the mesh, each block's triangles and orientation, and (as
/// r carries them) the crack edges and the intersecting triangle pairs, with the times (read_seconds:
/// reading the blocks).
void print_naive_block_mc_stats(std::FILE* out, const std::string& name, const Multiblock& mb, double iso, const NaiveMcResult& r,
                                double read_seconds);

/// Crack edges of a welded mesh of `mb`'s blocks (block ids = indices into mb.blocks).
CrackEdgeStats multiblock_crack_edges(const Multiblock& mb, const WeldedMesh& w);

}  // namespace meshless
