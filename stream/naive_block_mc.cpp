#include "stream/naive_block_mc.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "kernels/hex_point_location.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/runner.hpp"
#include "formats/terminal_safe.hpp"
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

std::array<double, 2> multiblock_value_range(const Multiblock& mb) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& b : mb.blocks)
        for (std::int64_t n = 0; n < b.node_count(); ++n)
            if (b.is_valid(n) && std::isfinite(b.value[static_cast<std::size_t>(n)])) {
                lo = std::min(lo, b.value[static_cast<std::size_t>(n)]);
                hi = std::max(hi, b.value[static_cast<std::size_t>(n)]);
            }
    return {lo, hi};
}

void print_naive_block_mc_stats(std::FILE* out, const std::string& name, const Multiblock& mb, double iso, const NaiveMcResult& r,
                                double read_seconds) {
    const BlockMcTotals& tot = r.totals;
    const Mesh& mesh = r.mesh;
    long long all_degenerate = 0;
    for (const auto& o : r.census) all_degenerate += o.degenerate;
    std::fprintf(out,
                 "mc: %s: %zu block(s), iso %g: %lld cells, %lld active, skipped %lld with an invalid corner and %lld "
                 "collapsed/inverted crossed by the surface (of %lld collapsed/inverted); %zu vertices, %zu triangles; read %.3f s, "
                 "marching cubes %.3f s\n",
                 name.c_str(), mb.blocks.size(), iso, static_cast<long long>(tot.cells), static_cast<long long>(tot.active_cells),
                 static_cast<long long>(tot.skipped_invalid), static_cast<long long>(tot.skipped_degenerate), all_degenerate,
                 mesh.vertex_count(), mesh.triangle_count(), read_seconds, r.mc_seconds);
    std::vector<std::int64_t> per_block(mb.blocks.size(), 0);
    for (std::uint32_t b : mesh.block) ++per_block[b];
    for (std::size_t b = 0; b < mb.blocks.size(); ++b)
        std::fprintf(out, "mc:   block %zu '%s' (%lldx%lldx%lld, %s): %lld triangles\n", b, terminal_safe(mb.blocks[b].name).c_str(),
                     static_cast<long long>(mb.blocks[b].dims[0]), static_cast<long long>(mb.blocks[b].dims[1]),
                     static_cast<long long>(mb.blocks[b].dims[2]), r.census[b].left_handed() ? "left-handed" : "right-handed",
                     static_cast<long long>(per_block[b]));
    const CrackEdgeStats& cs = *r.cracks;
    const TrianglePairStats& ps = *r.pairs;
    std::fprintf(out,
                 "mc: welded by position: %lld vertices, %lld edges, %lld boundary, %lld crack edges (boundary edges inside "
                 "another block), %lld non-manifold, %lld degenerate triangles; %.3f s\n",
                 static_cast<long long>(cs.vertices), static_cast<long long>(cs.edges), static_cast<long long>(cs.boundary_edges),
                 static_cast<long long>(cs.crack_edges), static_cast<long long>(cs.nonmanifold_edges),
                 static_cast<long long>(cs.degenerate_triangles), r.crack_seconds);
    std::fprintf(out,
                 "mc: triangle pairs from different blocks: %lld intersecting, %lld duplicated (same vertices), %lld "
                 "box-overlapping candidates, %lld collinear triangles skipped; %.3f s\n",
                 static_cast<long long>(ps.intersecting), static_cast<long long>(ps.duplicates),
                 static_cast<long long>(ps.candidates), static_cast<long long>(ps.degenerate), r.pair_seconds);
}

}  // namespace meshless
