// The naive per-block marching cubes graph (stream/block_mc_stage.hpp): pieces of cell layers,
// welded by the sink, give exactly each block's one-piece mesh, blocks in order, for any thread
// count and batch size; block ids survive the PLY round trip; skipped cells are counted.
#include <catch2/catch.hpp>

#include "formats/ply_mesh.hpp"
#include "kernels/multiblock_fixtures.hpp"
#include "stream/block_mc_stage.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/naive_block_mc.hpp"
#include "stream/runner.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

Multiblock two_blocks() {
    Multiblock mb;
    mb.blocks.push_back(index_block("fine", {-10, -10, -10}, {14, 21, 21}, 0.1, sphere_field));
    mb.blocks.push_back(lattice_block("flipped", {12, 11, 11}, {-0.25, -1, -1}, {0.2, 0.2, 0.2}, sphere_field, true));
    mb.blocks.push_back(lattice_block("flat", {4, 4, 1}, {0, 0, 0}, {1, 1, 1}, sphere_field));  // no cells
    return mb;
}

Mesh graph(const Multiblock& mb, int threads, std::int64_t cells_per_batch, BlockMcTotals* tot = nullptr,
           const std::string& path = {}) {
    BlockMcSource source(mb, cells_per_batch);
    const BlockMcStage stage(mb, 0.6, block_census(mb, threads));
    MeshWeldSink sink(path);
    const Stage* stages[] = {&stage};
    run_pipeline(source, stages, sink, {threads});
    if (tot) *tot = stage.totals();
    return sink.mesh();
}

}  // namespace

TEST_CASE("block mc graph: welded pieces equal each block's one-piece mesh, for any threads and batch size", "[block_mc]") {
    const Multiblock mb = two_blocks();
    Mesh expect;
    for (std::size_t b = 0; b < mb.blocks.size(); ++b) {
        BlockMcStats st;
        std::vector<std::uint64_t> keys;
        const Mesh m = block_marching_cubes(mb.blocks[b], 0.6, block_orientation(mb.blocks[b]).left_handed(), 0,
                                            mb.blocks[b].dims[2], static_cast<std::uint32_t>(b), st, keys);
        const auto base = static_cast<std::uint32_t>(expect.vertex_count());
        expect.xyz.insert(expect.xyz.end(), m.xyz.begin(), m.xyz.end());
        for (std::uint32_t t : m.tri) expect.tri.push_back(base + t);
        expect.block.insert(expect.block.end(), m.block.begin(), m.block.end());
    }
    REQUIRE(expect.triangle_count() > 0);
    for (std::int64_t per : {std::int64_t{1}, std::int64_t{500}, std::int64_t{1} << 20})
        for (int threads : {1, 2, 4}) {
            INFO("cells per batch " << per << ", threads " << threads);
            BlockMcTotals tot;
            const Mesh m = graph(mb, threads, per, &tot);
            CHECK(m.xyz == expect.xyz);
            CHECK(m.tri == expect.tri);
            CHECK(m.block == expect.block);
            CHECK(m.normals.empty());
            CHECK(tot.cells == 13 * 20 * 20 + 11 * 10 * 10);
            CHECK(tot.skipped_invalid == 0);
        }
}

TEST_CASE("block mc graph: the PLY carries a per-face block id", "[block_mc]") {
    const Multiblock mb = two_blocks();
    TempDir dir("block-mc");
    const std::string path = (dir / "naive.ply").string();
    const Mesh m = graph(mb, 2, 300, nullptr, path);
    const Mesh r = read_ply_mesh(path);
    CHECK(r.block == m.block);
    CHECK(r.tri == m.tri);
    CHECK(r.xyz == m.xyz);
    // block 1 lies in x >= -0.25: every one of its triangles is there, and block 0's in x <= 0.3
    for (std::size_t t = 0; t < r.triangle_count(); ++t)
        for (int q = 0; q < 3; ++q) {
            const float x = r.xyz[3 * r.tri[3 * t + q]];
            if (r.block[t] == 1) REQUIRE(x >= -0.25f - 1e-6f);
            else REQUIRE(x <= 0.3f + 1e-6f);
        }
    std::size_t ones = 0;
    for (auto b : r.block) ones += b == 1;
    CHECK(ones > 0);
    CHECK(ones < r.block.size());
}

TEST_CASE("block mc graph: the parallel census equals block_orientation per block", "[block_mc]") {
    Multiblock mb = two_blocks();
    mb.blocks[0].node[static_cast<std::size_t>(mb.blocks[0].index(3, 3, 3))] = mb.blocks[0].node[static_cast<std::size_t>(mb.blocks[0].index(2, 2, 2))];
    for (int threads : {1, 3}) {
        const auto census = block_census(mb, threads);
        REQUIRE(census.size() == 3);
        for (std::size_t b = 0; b < 3; ++b) {
            const BlockOrientation o = block_orientation(mb.blocks[b]);
            CHECK(census[b].positive == o.positive);
            CHECK(census[b].negative == o.negative);
            CHECK(census[b].degenerate == o.degenerate);
            CHECK(census[b].invalid == o.invalid);
        }
        CHECK(census[0].degenerate > 0);
        CHECK(census[1].left_handed());
    }
    CHECK_THROWS_AS(BlockMcStage(mb, 0.6, {}), std::invalid_argument);
}

TEST_CASE("block mc graph: blanked nodes skip their cells", "[block_mc]") {
    Multiblock mb = two_blocks();
    auto& b = mb.blocks[0];
    b.valid.assign(static_cast<std::size_t>(b.node_count()), 1);
    for (std::int64_t j = 0; j < b.dims[1]; ++j) b.valid[static_cast<std::size_t>(b.index(6, j, 10))] = 0;  // a line of nodes
    BlockMcTotals tot;
    graph(mb, 2, 400, &tot);
    CHECK(tot.skipped_invalid == 4 * 20);
}

TEST_CASE("naive_block_marching_cubes: the graph's mesh and the kernels' statistics in one call", "[block_mc]") {
    Multiblock semi;  // fine x in [-1, 0], coarse x in [0, 1]: cracks at x = 0
    semi.blocks.push_back(index_block("fine", {-10, -10, -10}, {11, 21, 21}, 0.1, sphere_field));
    semi.blocks.push_back(index_block("coarse", {0, -5, -5}, {6, 11, 11}, 0.2, sphere_field));
    const NaiveMcResult r1 = naive_block_marching_cubes(semi, 0.6, 1, {}, true);
    const NaiveMcResult r3 = naive_block_marching_cubes(semi, 0.6, 3, {}, true);
    REQUIRE(r1.cracks);
    REQUIRE(r1.pairs);
    CHECK(r1.cracks->crack_edges > 0);
    CHECK(r1.cracks->crack_edges == r3.cracks->crack_edges);
    CHECK(r1.pairs->intersecting == r3.pairs->intersecting);
    CHECK(r1.mesh.xyz == r3.mesh.xyz);
    CHECK(r1.mesh.tri == graph(semi, 2, 1000).tri);
    const NaiveMcResult quiet = naive_block_marching_cubes(semi, 0.6, 2);
    CHECK_FALSE(quiet.cracks);
    CHECK(quiet.mesh.block == r1.mesh.block);
    CHECK(quiet.census.size() == 2);
}
