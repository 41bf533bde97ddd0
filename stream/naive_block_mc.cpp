#include "stream/naive_block_mc.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>

#include "kernels/hex_point_location.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/runner.hpp"
#include "stream/seconds_since.hpp"

namespace meshless {

CrackEdgeStats multiblock_crack_edges(const Multiblock& mb, const WeldedMesh& w) {
    std::vector<BoundaryEdge> boundary;
    CrackEdgeStats cs = edge_census(w, boundary);
    if (boundary.empty()) return cs;
    // locators over the cells near the boundary edges only
    const double inf = std::numeric_limits<double>::infinity();
    Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
    for (const auto& e : boundary) {
        lo = {std::min(lo.x, e.midpoint.x), std::min(lo.y, e.midpoint.y), std::min(lo.z, e.midpoint.z)};
        hi = {std::max(hi.x, e.midpoint.x), std::max(hi.y, e.midpoint.y), std::max(hi.z, e.midpoint.z)};
    }
    std::vector<std::unique_ptr<BlockCellLocator>> locators;
    for (const auto& b : mb.blocks) locators.push_back(std::make_unique<BlockCellLocator>(b, 1e-3, lo, hi));
    for (const auto& e : boundary)
        for (std::size_t b = 0; b < locators.size(); ++b)
            if (b != e.block && locators[b]->contains(e.midpoint)) {
                ++cs.crack_edges;
                break;
            }
    return cs;
}

NaiveMcResult naive_block_marching_cubes(const Multiblock& mb, double iso, int threads, const std::string& ply_path,
                                         bool stats, GeometryFormat format, VtpOptions vtp) {
    NaiveMcResult r;
    auto t0 = std::chrono::steady_clock::now();
    BlockMcSource source(mb);
    const BlockMcStage stage(mb, iso, block_census(mb, threads));
    if (vtp.threads == 0) vtp.threads = threads;
    MeshWeldSink sink(ply_path, format, vtp);
    const Stage* stages[] = {&stage};
    run_pipeline(source, stages, sink, {threads});
    r.mc_seconds = seconds_since(t0);
    r.totals = stage.totals();
    r.census = stage.orientation();
    r.mesh = sink.mesh();
    if (!stats) return r;
    t0 = std::chrono::steady_clock::now();
    const WeldedMesh w = weld_by_position(r.mesh);
    r.cracks = multiblock_crack_edges(mb, w);
    r.crack_seconds = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    r.pairs = count_intersecting_triangle_pairs(w.xyz, w.tri, w.block);
    r.pair_seconds = seconds_since(t0);
    return r;
}

}  // namespace meshless
