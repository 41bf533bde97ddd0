// The scattered-data isosurface graph (dissertation sections 5.4-5.6): StencilSource ->
// StencilSeedStage -> FieldProjectStage, against oracles: the work units (dense, never spanning a
// row, every stencil once, a range of whole rows for the MPI ranks), seeds of a sampled sphere
// projected onto the exact distance field (on the sphere within the Newton tolerance, normals from
// the projection), and identical bytes for 1, 2 and 3 threads.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "kernels/scattered_binning_grid.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/stencil_seed_stage.hpp"
#include "stream/stencil_source.hpp"

#include "stream/sphere_distance_field.hpp"

using namespace meshless;

namespace {

struct Collect final : Sink {
    PayloadSet takes() const override { return Payload::points; }
    std::vector<PointRecord> points;
    std::vector<std::uint64_t> seqs;
    void consume(Batch&& b) override {
        seqs.push_back(b.seq);
        REQUIRE(b.kind == RecordKind::point);
        points.insert(points.end(), b.points.begin(), b.points.end());
    }
};

}  // namespace

TEST_CASE("stencil source: dense units within rows, every stencil once", "[stream][scattered]") {
    const StencilGrid sg({18, 10, 3});  // 9 x 5 x 1 stencils
    StencilSource src(sg, 4);
    std::vector<int> seen(static_cast<std::size_t>(sg.total()), 0);
    std::uint64_t seq = 0;
    while (auto b = src.next()) {
        CHECK(b->seq == seq++);
        CHECK(b->kind == RecordKind::seed);
        CHECK(b->cells.k1 > b->cells.k0);
        CHECK(b->cells.k1 - b->cells.k0 <= 4);
        CHECK(b->cells.k0 / 9 == (b->cells.k1 - 1) / 9);  // one row
        for (auto s = b->cells.k0; s < b->cells.k1; ++s) ++seen[static_cast<std::size_t>(s)];
    }
    for (int k : seen) CHECK(k == 1);
    StencilSource part(sg, 18, 36, 8);
    std::int64_t first = -1, last = -1;
    while (auto b = part.next()) {
        if (first < 0) first = b->cells.k0;
        last = b->cells.k1;
    }
    CHECK(first == 18);
    CHECK(last == 36);
}

TEST_CASE("stencil graph: a sampled sphere onto the distance field, same bytes for any thread count", "[stream][scattered]") {
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Vec3> pos;
    for (int i = 0; i < 6000; ++i) pos.push_back({u(rng), u(rng), u(rng)});
    std::vector<double> val(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) val[i] = norm(pos[i]);
    const BinningGrid g = make_binning_grid(pos);
    const BinnedPoints b = bin_points(g, pos);
    const test::SphereDistance f;
    const StencilInput in{g, b, pos, val, f};
    const double iso = 0.55;
    FieldProjectParams np;
    np.seed_tolerance = 0.01;
    std::vector<PointRecord> first;
    for (int threads : {1, 2, 3}) {
        INFO("threads " << threads);
        StencilSource src{StencilGrid(g.dims)};
        const StencilSeedStage seed(in, iso, 3);
        const FieldProjectStage project(f, iso, np);
        const Stage* stages[] = {&seed, &project};
        Collect sink;
        run_pipeline(src, stages, sink, {threads});
        for (std::size_t i = 0; i < sink.seqs.size(); ++i) CHECK(sink.seqs[i] == i);
        REQUIRE(sink.points.size() > 2000);
        const auto st = seed.stats();
        CHECK(st.seeds == project.stats().input);
        CHECK(project.stats().converged == static_cast<std::int64_t>(sink.points.size()));
        if (threads == 1) {
            first = sink.points;
            for (const PointRecord& p : sink.points) {
                const Vec3 x{p.pos[0], p.pos[1], p.pos[2]};
                CHECK(std::abs(norm(x) - iso) < 0.01 * g.diagonal() + 1e-6);
                // the projection stage's normal: against the field's gradient (VTK's convention)
                CHECK(dot(Vec3{p.normal[0], p.normal[1], p.normal[2]}, normalized(x)) == Approx(-1).margin(1e-5));
                CHECK(p.value == Approx(iso));
                CHECK(p.radius > 0);
            }
        } else {
            REQUIRE(sink.points.size() == first.size());
            CHECK(std::memcmp(sink.points.data(), first.data(), first.size() * sizeof(PointRecord)) == 0);
        }
    }
}
