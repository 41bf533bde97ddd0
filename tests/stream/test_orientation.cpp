// Orientation like VTK (vtkFlyingEdges3D / vtkMarchingCubes / vtkContourFilter with
// ComputeNormals) on every path that emits normals or triangles, against analytic oracles:
//   a ball, high values inside (1 - |p| on [-1, 1]^3, iso 0.4: radius 0.6), and its complement, the
//   distance |p| (high values outside, iso 0.6).
// Every point normal is -grad f / |grad f|: on the ball it points outwards (dot with the radial
// direction > 0.99), on the distance field inwards (< -0.99), for the chapter-3 projections (approx,
// exact, none; fused and two-stage give the same bytes), for the field Newton projection of
// multiblock seeds (a split of the volume, one MPU field) and of scattered seeds (a random sample,
// the default field). Marching cubes: triangles wind counter-clockwise seen from the normal side, so
// the mesh around the ball has positive signed volume (about 4/3 pi 0.6^3) and the distance field's
// the opposite; every triangle's geometric normal agrees with its three vertex normals.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "kernels/analytic_volumes.hpp"
#include "kernels/block_cell_seeds.hpp"
#include "kernels/field_params.hpp"
#include "kernels/make_field.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/multiblock_split.hpp"
#include "kernels/scattered_binning_grid.hpp"
#include "stream/block_cell_source.hpp"
#include "stream/block_seed_stage.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"
#include "stream/runner.hpp"
#include "stream/stencil_seed_stage.hpp"
#include "stream/stencil_source.hpp"

using namespace meshless;

namespace {

constexpr std::int64_t kN = 41;  // samples per axis over [-1, 1]
constexpr double kR = 0.6;       // the sphere of both fields

/// The analytic distance volume |p| (high outside), or the ball 1 - |p| (high inside).
Volume field_volume(bool ball) {
    Volume v = make_analytic_volume(AnalyticField::sphere, kN);
    if (ball) {
        float* f = reinterpret_cast<float*>(v.bytes.data());
        for (std::int64_t i = 0; i < v.grid.voxel_count(); ++i) f[i] = 1.0f - f[i];
    }
    return v;
}
double iso_of(bool ball) { return ball ? 1.0 - kR : kR; }

struct Collect final : Sink {
    PayloadSet takes() const override { return Payload::points; }
    std::vector<PointRecord> points;
    void consume(Batch&& b) override { points.insert(points.end(), b.points.begin(), b.points.end()); }
};

/// min and max over the points of n . p / |p| (the radial component of the unit normal).
std::array<double, 2> radial_range(const std::vector<PointRecord>& pts) {
    double lo = 2, hi = -2;
    for (const PointRecord& p : pts) {
        const Vec3 x{p.pos[0], p.pos[1], p.pos[2]}, n{p.normal[0], p.normal[1], p.normal[2]};
        const double c = dot(n, normalized(x)) / norm(n);
        lo = std::min(lo, c);
        hi = std::max(hi, c);
    }
    return {lo, hi};
}

/// Checks VTK's orientation: outwards (ball) or inwards (distance field) everywhere.
void check_radial(const std::vector<PointRecord>& pts, bool ball) {
    REQUIRE(pts.size() > 500);
    const auto r = radial_range(pts);
    INFO((ball ? "ball" : "distance") << ": n . p/|p| in [" << r[0] << ", " << r[1] << "] over " << pts.size() << " points");
    if (ball) CHECK(r[0] > 0.99);
    else CHECK(r[1] < -0.99);
}

Vec3 vertex(const Mesh& m, std::uint32_t i) { return {m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]}; }
Vec3 vnormal(const Mesh& m, std::uint32_t i) { return {m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]}; }

}  // namespace

TEST_CASE("orientation: chapter-3 projections give -grad f normals, fused and two-stage alike", "[orientation]") {
    for (bool ball : {true, false}) {
        const Volume v = field_volume(ball);
        for (Projection mode : {Projection::approx, Projection::exact, Projection::none}) {
            INFO(to_string(mode));
            CollectSink fused, staged;
            run_isosplat(v.view(), iso_of(ball), mode, SamplingParams{}, fused, RunOptions{2}, PipelineShape::fused);
            run_isosplat(v.view(), iso_of(ball), mode, SamplingParams{}, staged, RunOptions{2}, PipelineShape::two_stage);
            check_radial(fused.points, ball);
            REQUIRE(fused.points.size() == staged.points.size());
            CHECK(std::memcmp(fused.points.data(), staged.points.data(), fused.points.size() * sizeof(PointRecord)) == 0);
        }
    }
}

TEST_CASE("orientation: marching cubes winds counter-clockwise seen from -grad f", "[orientation]") {
    for (bool ball : {true, false}) {
        INFO((ball ? "ball" : "distance"));
        const Mesh m = marching_cubes(field_volume(ball).view(), iso_of(ball));
        REQUIRE(m.triangle_count() > 1000);
        double vol = 0;
        std::size_t disagree = 0;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const std::uint32_t* q = &m.tri[3 * t];
            const Vec3 a = vertex(m, q[0]), b = vertex(m, q[1]), c = vertex(m, q[2]);
            vol += dot(a, cross(b, c)) / 6;
            const Vec3 g = cross(b - a, c - a);
            for (int k = 0; k < 3; ++k) disagree += dot(g, vnormal(m, q[k])) <= 0;
        }
        const double ball_volume = 4.0 / 3.0 * M_PI * kR * kR * kR;
        CHECK(vol == Approx(ball ? ball_volume : -ball_volume).epsilon(0.01));
        CHECK(disagree == 0);
        // and the vertex normals themselves: outwards on the ball, inwards on the distance field
        std::vector<PointRecord> pts(m.vertex_count());
        for (std::uint32_t i = 0; i < m.vertex_count(); ++i) {
            for (int d = 0; d < 3; ++d) {
                pts[i].pos[d] = m.xyz[3 * i + d];
                pts[i].normal[d] = m.normals[3 * i + d];
            }
        }
        check_radial(pts, ball);
    }
}

TEST_CASE("orientation: the field Newton projection of multiblock seeds gives -grad f normals", "[orientation][multiblock]") {
    for (bool ball : {true, false}) {
        const Volume v = field_volume(ball);
        const Multiblock mb = split_volume(v.view(), SplitLayout::overlapping);
        FieldParams fp;
        fp.kind = FieldKind::mpu;
        const auto field = make_field(to_point_set(mb), fp);
        const double iso = iso_of(ball);
        const BlockSeedPlan plan = plan_block_seeds(mb, iso);
        BlockCellSource source(plan.first_cell, block_seed_unit_cells(2));
        BlockSeedStage seed(mb, plan, iso, 2);
        FieldProjectStage proj(*field, iso, FieldProjectParams{});
        Collect sink;
        const Stage* stages[] = {&seed, &proj};
        run_pipeline(source, stages, sink, {2});
        check_radial(sink.points, ball);
    }
}

TEST_CASE("orientation: the field Newton projection of scattered seeds gives -grad f normals", "[orientation][scattered]") {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    PointSet ps;
    for (int i = 0; i < 12000; ++i) ps.pos.push_back({u(rng), u(rng), u(rng)});
    ps.blocks.push_back({"scattered", {static_cast<std::int64_t>(ps.pos.size()), 1, 1}, 0, ps.pos.size()});
    for (bool ball : {true, false}) {
        ps.value.clear();
        for (const Vec3& p : ps.pos) ps.value.push_back(ball ? 1.0 - norm(p) : norm(p));
        const auto field = make_field(ps, FieldParams{});
        const BinningGrid g = make_binning_grid(ps.pos);
        const BinnedPoints b = bin_points(g, ps.pos);
        const StencilInput in{g, b, ps.pos, ps.value, *field};
        const double iso = iso_of(ball);
        StencilSource src{StencilGrid(g.dims)};
        const StencilSeedStage seed(in, iso, 2);
        const FieldProjectStage proj(*field, iso, FieldProjectParams{});
        const Stage* stages[] = {&seed, &proj};
        Collect sink;
        run_pipeline(src, stages, sink, {2});
        check_radial(sink.points, ball);
    }
}
