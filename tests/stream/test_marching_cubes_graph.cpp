// Marching cubes through the stage graph (stream/marching_cubes_stage.hpp, stream/mesh_sink.hpp):
// welded slabs give exactly marching_cubes()'s mesh (same arrays, any thread count, degenerate
// vertices on grid points included); welded bricks give the in-memory vertex set and triangles.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "kernels/analytic_volumes.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/ooc_test_util.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/marching_cubes_stage.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/runner.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

Mesh graph_mc(const Volume& v, double iso, int threads, std::int64_t cells_per_batch, McStats* st = nullptr) {
    McSlabSource source(v.grid, cells_per_batch);
    MarchingCubesStage stage(v.view(), iso);
    MeshWeldSink sink;
    const Stage* stages[] = {&stage};
    run_pipeline(source, stages, sink, {threads});
    if (st) *st = stage.stats();
    return sink.mesh();
}

/// uint8 quantisation of an analytic field: integer isovalues put vertices exactly on grid points.
Volume quantised(AnalyticField f, std::int64_t n) {
    const Volume fv = make_analytic_volume(f, n);
    Volume v(fv.grid, SampleType::u8);
    const float* src = reinterpret_cast<const float*>(fv.bytes.data());
    for (std::size_t i = 0; i < v.bytes.size(); ++i)
        v.bytes[i] = static_cast<std::byte>(std::clamp(std::lround(src[i] * 80 + 128), 0L, 255L));
    return v;
}

}  // namespace

TEST_CASE("mc graph over slabs: exactly marching_cubes(), any threads and slab size", "[mc-graph]") {
    struct Case {
        Volume v;
        double iso;
    };
    const Case cases[] = {{make_analytic_volume(AnalyticField::gyroid, 45), 0.1},
                          {make_analytic_volume(AnalyticField::torus, 40), 0.25},
                          {quantised(AnalyticField::gyroid, 41), 128.0},  // degenerate: vertices on grid points
                          {quantised(AnalyticField::sphere, 33), 180.5}};
    for (const Case& c : cases) {
        McStats ref_st;
        const Mesh ref = marching_cubes(c.v.view(), c.iso, &ref_st);
        REQUIRE(ref.triangle_count() > 100);
        for (std::int64_t per : {std::int64_t{1}, std::int64_t{3000}, std::int64_t{20000}, McSlabSource::kMcCellsPerBatch}) {
            for (int threads : {1, 3}) {
                McStats st;
                const Mesh m = graph_mc(c.v, c.iso, threads, per, &st);
                INFO("cells per batch " << per << ", threads " << threads);
                CHECK(m.xyz == ref.xyz);
                CHECK(m.normals == ref.normals);
                CHECK(m.tri == ref.tri);
                CHECK(st.active_cells == ref_st.active_cells);
            }
        }
    }
}

TEST_CASE("mc graph over bricks: the in-memory vertex set and triangles, any threads", "[mc-graph]") {
    // (this graph replaced ooc/brick_marching_cubes; commit 573a24e checked it gave that mesher's bytes)
    TempDir d("mcgraph");
    const Volume v = make_analytic_volume(AnalyticField::gyroid, 50);
    const std::string path = (d / "g.mlb").string();
    convert_volume(v, path, 16);
    const auto store = BrickStore::open(path);
    BrickCache cache(*store, 1 << 20);
    const BrickIndex index(*store);
    const double iso = 0.1;
    const Mesh ref = marching_cubes(v.view(), iso);
    auto positions = [](const Mesh& m) {
        std::vector<std::array<float, 3>> p(m.vertex_count());
        for (std::size_t i = 0; i < p.size(); ++i) p[i] = {m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]};
        std::sort(p.begin(), p.end());
        return p;
    };
    auto triangles = [](const Mesh& m) {  // each triangle as its corner positions, rotated to a canonical start
        std::vector<std::array<float, 9>> t(m.triangle_count());
        for (std::size_t i = 0; i < t.size(); ++i) {
            std::array<std::array<float, 3>, 3> c;
            for (int k = 0; k < 3; ++k)
                for (int d = 0; d < 3; ++d) c[k][d] = m.xyz[3 * m.tri[3 * i + k] + d];
            const auto first = std::min_element(c.begin(), c.end()) - c.begin();
            std::rotate(c.begin(), c.begin() + first, c.end());
            for (int k = 0; k < 3; ++k)
                for (int d = 0; d < 3; ++d) t[i][3 * k + d] = c[k][d];
        }
        std::sort(t.begin(), t.end());
        return t;
    };
    Mesh first;
    for (int threads : {1, 2}) {
        McBrickSource source(index.active(iso));
        MarchingCubesStage stage(*store, cache, iso);
        MeshWeldSink sink;
        const Stage* stages[] = {&stage};
        run_pipeline(source, stages, sink, {threads});
        const Mesh& m = sink.mesh();
        CHECK(m.vertex_count() == ref.vertex_count());
        CHECK(positions(m) == positions(ref));
        CHECK(triangles(m) == triangles(ref));  // same triangles, same orientation
        if (threads == 1) first = m;
        CHECK(m.xyz == first.xyz);
        CHECK(m.tri == first.tri);
    }
}

TEST_CASE("mesh sink refuses point batches", "[mc-graph]") {
    MeshWeldSink sink;
    RecordVectorSource points(std::vector<PointRecord>(3));
    CHECK_THROWS_WITH(run_pipeline(points, {}, sink), "stage graph: MeshWeldSink takes mesh pieces, RecordVectorSource gives points");
}
