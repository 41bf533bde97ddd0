// The MPU field grows with its points, not faster, on sharp-edged data (the case a CT's samples make:
// values that jump across a surface): the locals, the field's bytes and the regularised share, at N and
// 8N scattered samples of a step field (1 inside a ball, 0 outside), must grow within 1.3x of linear and
// keep ill-conditioned locals rare (the subdivision and Hardy's c follow the local point spacing).
// The octree deepens a level at a time (8x the leaves) as the points cross its split count, so the
// leaves grow as a staircase: 20,000 -> 40,000 points keep 4,096 leaves, 80,000 have 26,608; the test
// compares N and 8N, one whole step.
#include <catch2/catch.hpp>

#include <cmath>

#include "kernels/make_field.hpp"
#include "kernels/splitmix.hpp"

using namespace meshless;

namespace {

/// n uniform positions in the unit cube (fixed seed), value 1 within 0.3 of the centre, else 0.
PointSet step_samples(std::size_t n) {
    SplitMix rng{99};
    PointSet ps;
    ps.value_name = "value";
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 p{rng.unit(), rng.unit(), rng.unit()};
        const Vec3 d = p - Vec3{0.5, 0.5, 0.5};
        ps.pos.push_back(p);
        ps.value.push_back(dot(d, d) < 0.09 ? 1.0 : 0.0);
    }
    ps.blocks = {PointSetBlock{"step", {static_cast<std::int64_t>(n), 1, 1}, 0, n}};
    return ps;
}

}  // namespace

TEST_CASE("mpu on a step field: locals and bytes grow linearly with the points, regularised locals rare", "[kernels][mpu][scale]") {
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    FieldBuildStats small, large;
    const std::size_t n = 20000;
    (void)make_field(step_samples(n), fp, &small);
    (void)make_field(step_samples(8 * n), fp, &large);
    INFO("locals " << small.locals << " -> " << large.locals << ", bytes " << small.memory_bytes << " -> " << large.memory_bytes
                   << ", regularised " << small.regularised << " / " << large.regularised);
    REQUIRE(small.locals > 100);
    CHECK(static_cast<double>(large.locals) <= 1.3 * 8 * static_cast<double>(small.locals));
    CHECK(static_cast<double>(large.memory_bytes) <= 1.3 * 8 * static_cast<double>(small.memory_bytes));
    CHECK(static_cast<double>(large.regularised) <= 0.05 * static_cast<double>(large.locals));
    CHECK(static_cast<double>(small.regularised) <= 0.05 * static_cast<double>(small.locals));
}
