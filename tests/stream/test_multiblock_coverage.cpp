// Crack-free coverage of the multiblock/AMR isosurface (dissertation Figures 4.6-4.8) for
// every layout meshless split writes: an analytic volume (sphere, torus, gyroid; 33^3 over [-1,1]^3)
// split into overlapping, semi-conforming, non-conforming and rotated blocks and into a 3-level
// cell-centred AMR hierarchy (covered coarse cells marked as the readers do); one MPU field over
// every block's data; seeds -> Newton through the stage graph. Oracles (kernels/surface_coverage):
// >= 99.9% of a dense sampling of the true isosurface inside the data domain lies within one splat
// radius of an output point, the mean distance of the points to the true surface is <= 0.05 of
// the cell edge, and every normal follows VTK's convention (-grad f: none reversed, mean angle to
// -grad f under 2 degrees). The control: the same AMR hierarchy seeded on its unpadded lattices of cell centres
// leaves bands at box seams and domain faces unseeded and misses the coverage bound, so the test can
// fail.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "../test_size.hpp"
#include "kernels/amr_cover.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/block_cell_seeds.hpp"
#include "kernels/field_params.hpp"
#include "kernels/make_field.hpp"
#include "kernels/multiblock_split.hpp"
#include "kernels/surface_coverage.hpp"
#include "stream/block_cell_source.hpp"
#include "stream/block_seed_stage.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/runner.hpp"

using namespace meshless;

namespace {

struct Collect final : Sink {
    PayloadSet takes() const override { return Payload::points; }
    std::vector<Vec3> pos, normal;
    std::vector<float> radius;
    void consume(Batch&& b) override {
        for (const auto& p : b.points) {
            pos.push_back({p.pos[0], p.pos[1], p.pos[2]});
            normal.push_back({p.normal[0], p.normal[1], p.normal[2]});
            radius.push_back(p.radius);
        }
    }
};

struct Outcome {
    double coverage = 0, mean_distance = 0, mean_normal_deg = 0;
    std::size_t points = 0, reversed = 0;
};

Outcome run(AnalyticField f, SplitLayout layout, bool pad = true) {
    const std::int64_t n = 33;
    const double h = 2.0 / static_cast<double>(n - 1);
    const double iso = default_iso(f);
    const Volume v = make_analytic_volume(f, n);
    Multiblock mb;
    if (layout == SplitLayout::amr) {
        AmrParams p;
        p.iso = iso;
        p.tile = 4;
        mb = amr_to_multiblock(split_amr(v.view(), p));
        mark_amr_covered(mb);  // as read_multiblock does for AMR files
    } else {
        mb = split_volume(v.view(), layout);
    }
    const Multiblock seeds_mb = pad && has_cell_centred_blocks(mb) ? amr_seed_blocks(mb) : mb;
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    const auto field = make_field(to_point_set(mb), fp);
    const BlockSeedPlan plan = plan_block_seeds(seeds_mb, iso);
    BlockCellSource source(plan.first_cell, block_seed_unit_cells(3));
    BlockSeedStage seed(seeds_mb, plan, iso, 3);
    FieldProjectStage proj(*field, iso, FieldProjectParams{});
    Collect sink;
    const Stage* stages[] = {&seed, &proj};
    run_pipeline(source, stages, sink, {2});
    SurfaceSampling s;
    s.spacing = h / 4;
    const auto samples = sample_isosurface(f, iso, Box3{{-1, -1, -1}, {1, 1, 1}}, s);
    Outcome o;
    o.points = sink.pos.size();
    o.coverage = surface_coverage(samples, sink.pos, sink.radius).fraction();
    const PointErrors e = point_errors(f, iso, sink.pos, sink.normal);
    o.mean_distance = e.mean_distance / h;
    o.mean_normal_deg = e.mean_normal_deg;
    o.reversed = e.reversed;
    return o;
}

}  // namespace

TEST_CASE("multiblock isosurface: crack-free coverage of analytic surfaces in every layout, AMR included", "[multiblock][coverage]") {
    // (the sanitizer tier: the sphere alone, every layout; the fields' numerics are the Release tier's)
    const std::vector<AnalyticField> fields = test::reduced_test_sizes()
                                                  ? std::vector<AnalyticField>{AnalyticField::sphere}
                                                  : std::vector<AnalyticField>{AnalyticField::sphere, AnalyticField::torus, AnalyticField::gyroid};
    for (AnalyticField f : fields)
        for (SplitLayout l : {SplitLayout::overlapping, SplitLayout::semi_conforming, SplitLayout::non_conforming,
                              SplitLayout::rotated, SplitLayout::amr}) {
            const Outcome o = run(f, l);
            INFO(to_string(f) << " / " << to_string(l) << ": " << o.points << " points, coverage " << o.coverage
                              << ", mean distance " << o.mean_distance << " cell edges, normals: mean "
                              << o.mean_normal_deg << " deg from -grad f, " << o.reversed << " reversed");
            CHECK(o.points > 0);
            CHECK(o.coverage >= 0.999);
            CHECK(o.mean_distance <= 0.05);
            CHECK(o.reversed == 0);
            CHECK(o.mean_normal_deg < 2.0);
        }
}

TEST_CASE("multiblock isosurface: AMR boxes seeded on their unpadded centre lattices leave gaps (the control)", "[multiblock][coverage]") {
    const Outcome o = run(AnalyticField::gyroid, SplitLayout::amr, /*pad=*/false);
    INFO("unpadded: coverage " << o.coverage);
    CHECK(o.coverage < 0.999);
}
