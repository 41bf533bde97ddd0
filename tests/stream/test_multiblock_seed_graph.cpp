// The multiblock/AMR isosurface graph (dissertation section 4.4): BlockCellSource -> BlockSeedStage ->
// FieldProjectStage, against oracles: the work units (dense, bounded, never spanning blocks, every
// cell once), seeds of a sampled sphere projected onto the exact distance field (on the sphere within
// the tolerance, radius = 2(1 + d/l) base, block ids through), onto an MPU field built from the
// block's nodes (on that field within the tolerance, near the true sphere), a seed at the centre of
// the distance field (vanishing gradient: dropped and counted), the seam test (two overlapping,
// rotated blocks of different resolutions: their points lie on one surface, while their naive
// marching-cubes seeds do not), identical bytes for any thread count, and seed / point-with-block
// streams through the pipe endpoints.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>

#include "formats/point_stream.hpp"
#include "kernels/barycentric_lattice.hpp"
#include "kernels/block_cell_seeds.hpp"
#include "kernels/errors.hpp"
#include "kernels/field_params.hpp"
#include "kernels/marching_cubes_table.hpp"
#include "kernels/make_field.hpp"
#include "kernels/multiblock_splat_radius.hpp"
#include "stream/block_cell_source.hpp"
#include "stream/block_seed_stage.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/stream_endpoints.hpp"

#include "kernels/multiblock_fixtures.hpp"
#include "stream/sphere_distance_field.hpp"

using namespace meshless;

namespace {

using Fn = std::function<double(const Vec3&)>;
using test::mapped_block;
using test::SphereDistance;

double sphere(const Vec3& p) { return norm(p); }

/// Keeps points and their block ids, in order.
struct BlockCollect final : Sink {
    PayloadSet takes() const override { return {Payload::points, Payload::seeds}; }
    std::vector<PointRecord> points;
    std::vector<std::uint32_t> block;
    std::vector<SeedRecord> seeds;
    void consume(Batch&& b) override {
        if (b.kind == RecordKind::seed) {
            seeds.insert(seeds.end(), b.seeds.begin(), b.seeds.end());
            return;
        }
        REQUIRE(b.kind == RecordKind::point);
        REQUIRE(b.point_block.size() == b.points.size());
        points.insert(points.end(), b.points.begin(), b.points.end());
        block.insert(block.end(), b.point_block.begin(), b.point_block.end());
    }
};

struct GraphRun {
    BlockCollect out;
    BlockSeedStats seeds;
    FieldNewtonStats newton;
};

/// The whole graph; field null: seeds only.
GraphRun run_graph(const Multiblock& mb, double iso, int n, const Field* field, int threads, FieldProjectParams p = {}) {
    const BlockSeedPlan plan = plan_block_seeds(mb, iso);
    BlockCellSource source(plan.first_cell, block_seed_unit_cells(n));
    BlockSeedStage seed(mb, plan, iso, n);
    GraphRun r;
    if (field) {
        FieldProjectStage project(*field, iso, p);
        const Stage* stages[] = {&seed, &project};
        run_pipeline(source, stages, r.out, {threads});
        r.newton = project.stats();
    } else {
        const Stage* stages[] = {&seed};
        run_pipeline(source, stages, r.out, {threads});
    }
    r.seeds = seed.stats();
    return r;
}

Vec3 at(const PointRecord& p) { return {p.pos[0], p.pos[1], p.pos[2]}; }
Vec3 at(const SeedRecord& p) { return {p.pos[0], p.pos[1], p.pos[2]}; }
Vec3 normal_of(const PointRecord& p) { return {p.normal[0], p.normal[1], p.normal[2]}; }
Vec3 normal_of(const SeedRecord& p) { return {p.normal[0], p.normal[1], p.normal[2]}; }

Multiblock sphere_block(std::int64_t cells, double lo = -1, double hi = 1) {
    Multiblock mb;
    const double h = (hi - lo) / static_cast<double>(cells);
    mb.blocks.push_back(mapped_block({cells + 1, cells + 1, cells + 1}, [=](double i, double j, double k) {
        return Vec3{lo + h * i, lo + h * j, lo + h * k};
    }, sphere));
    return mb;
}

}  // namespace

TEST_CASE("block cell source: dense sequence, bounded units within one block, every cell once", "[multiblock-graph]") {
    const std::vector<std::int64_t> first{0, 10, 10, 10000, 10001};  // blocks of 10, 0, 9990 and 1 cells
    BlockCellSource src(first, 1000);
    std::int64_t expect = 0;
    std::uint64_t seq = 0;
    while (auto b = src.next()) {
        CHECK(b->seq == seq++);
        CHECK(b->kind == RecordKind::seed);
        CHECK(b->cells.k0 == expect);
        CHECK(b->cells.k1 > b->cells.k0);
        CHECK(b->cells.k1 - b->cells.k0 <= 1000);
        const auto blk = std::upper_bound(first.begin(), first.end() - 1, b->cells.k0) - first.begin() - 1;
        CHECK(b->cells.k1 <= first[static_cast<std::size_t>(blk) + 1]);
        expect = b->cells.k1;
    }
    CHECK(expect == 10001);
    CHECK(src.emitted() == 1 + 10 + 1);
    for (int n : {1, 2, 3, 8, 64})
        CHECK(block_seed_unit_cells(n) * kMcMaxTriangles * static_cast<std::int64_t>(lattice_size(n)) <=
              static_cast<std::int64_t>(kMaxBatchRecords));
}

TEST_CASE("seeds of a sampled sphere projected onto the distance field lie on the sphere within the tolerance", "[multiblock-graph]") {
    const Multiblock mb = sphere_block(14);
    const SphereDistance f;
    FieldProjectParams p;
    p.seed_tolerance = 0.01;
    const GraphRun r = run_graph(mb, 0.6, 3, &f, 2, p);
    const double diag = 2.0 / 14 * std::sqrt(3.0);
    REQUIRE(r.newton.input == r.seeds.seeds);
    CHECK(r.newton.converged == r.newton.input);
    REQUIRE(r.out.points.size() == static_cast<std::size_t>(r.seeds.seeds));
    for (std::size_t i = 0; i < r.out.points.size(); ++i) {
        const PointRecord& q = r.out.points[i];
        CHECK(std::abs(norm(at(q)) - 0.6) < 0.01 * diag + 1e-6);  // tolerance, plus float rounding
        CHECK(dot(normal_of(q), normalized(at(q))) < -0.9999);  // -grad f: the distance grows outwards
        CHECK(q.value == 0.6f);
        CHECK(r.out.block[i] == 0u);
    }
}

TEST_CASE("seed projection: radius 2(1 + d/l) base, block ids through, relative tolerance", "[multiblock-graph]") {
    const SphereDistance f;
    std::vector<SeedRecord> seeds;
    for (int i = 0; i < 50; ++i) {
        SeedRecord s{};
        const Vec3 d = normalized(Vec3{std::cos(0.7 * i), std::sin(1.3 * i), 0.3 * std::cos(0.2 * i)});
        const Vec3 p = d * (0.5 + 0.004 * (i % 11));  // up to 0.04 off the sphere of radius 0.5
        s.pos[0] = static_cast<float>(p.x);
        s.pos[1] = static_cast<float>(p.y);
        s.pos[2] = static_cast<float>(p.z);
        s.base_radius = 0.01f + 0.001f * static_cast<float>(i % 5);
        s.cell_diagonal = 0.1f + 0.01f * static_cast<float>(i % 3);
        s.block = static_cast<std::uint32_t>(i % 4 + 10);
        seeds.push_back(s);
    }
    SeedRecord centre{};  // the distance field's gradient vanishes at its centre
    centre.cell_diagonal = 0.1f;
    centre.base_radius = 0.01f;
    seeds.insert(seeds.begin() + 7, centre);
    Batch b;
    b.kind = RecordKind::seed;
    b.seeds = seeds;
    FieldProjectStage stage(f, 0.5);
    stage.process(b);
    REQUIRE(b.kind == RecordKind::point);
    REQUIRE(b.points.size() == 50);
    REQUIRE(b.point_block.size() == 50);
    CHECK(stage.stats().flat == 1);
    CHECK(stage.stats().dropped() == 1);
    CHECK(b.seeds.empty());
    for (std::size_t i = 0, k = 0; i < seeds.size(); ++i) {
        if (i == 7) continue;
        const SeedRecord& s = seeds[i];
        const PointRecord& q = b.points[k];
        const double d = norm(at(q) - at(s));
        CHECK(std::abs(norm(at(q)) - 0.5) <= 0.01 * s.cell_diagonal + 1e-6);
        CHECK_THAT(q.radius, Catch::WithinRel(multiblock_splat_radius(s.base_radius, d, s.cell_diagonal), 1e-5));
        CHECK(q.radius >= 2 * s.base_radius);
        CHECK(b.point_block[k] == s.block);
        ++k;
    }
    // a travel limit drops (and counts) seeds that would move farther than F cell diagonals
    Batch c;
    c.kind = RecordKind::seed;
    c.seeds = seeds;
    FieldProjectParams lim;
    lim.seed_max_travel = 0.2;  // 0.2 x (0.10 .. 0.12): seeds more than ~0.02 off the sphere are too far
    FieldProjectStage limited(f, 0.5, lim);
    limited.process(c);
    CHECK(limited.stats().too_far > 0);
    CHECK(static_cast<std::int64_t>(c.points.size()) == limited.stats().converged);
    for (std::size_t k = 0; k < c.points.size(); ++k) CHECK(c.points[k].radius <= 2 * (1 + 0.2) * 0.014f + 1e-6);
}

TEST_CASE("seeds projected onto an MPU field built from the block: on the field, near the true sphere", "[multiblock-graph]") {
    const Multiblock mb = sphere_block(12);
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    const auto field = make_field(to_point_set(mb), fp);
    const GraphRun r = run_graph(mb, 0.6, 2, field.get(), 2);
    const double h = 2.0 / 12, diag = h * std::sqrt(3.0);
    CHECK(r.newton.converged >= r.newton.input * 99 / 100);
    REQUIRE(!r.out.points.empty());
    double worst_field = 0, worst_sphere = 0;
    for (const PointRecord& q : r.out.points) {
        Vec3 g;
        const double v = field->value(at(q), &g);
        worst_field = std::max(worst_field, std::abs(v - 0.6) / norm(g));
        worst_sphere = std::max(worst_sphere, std::abs(norm(at(q)) - 0.6));
    }
    CHECK(worst_field <= 0.01 * diag + 1e-6);
    CHECK(worst_sphere < 0.05 * h);
}

TEST_CASE("seam test: overlapping rotated blocks of different resolutions give points on one surface", "[multiblock-graph]") {
    // block 0: [-1, 0.3] x [-1, 1]^2, h = 0.1; block 1: [-0.3, 1] x [-1, 1]^2 at h = 0.16, rotated by
    // 17 degrees about x (no shared nodes). The field: a bumpy sphere, so the blocks' own trilinear
    // surfaces disagree in the overlap |x| < 0.3.
    const Fn f = [](const Vec3& p) { return norm(p) + 0.08 * std::sin(5 * p.x) * std::cos(4 * p.y) * std::sin(3 * p.z + 1); };
    Multiblock mb;
    mb.blocks.push_back(mapped_block({14, 21, 21}, [](double i, double j, double k) { return Vec3{-1 + 0.1 * i, -1 + 0.1 * j, -1 + 0.1 * k}; }, f));
    const double a = 17 * 3.14159265358979 / 180;
    mb.blocks.push_back(mapped_block({9, 14, 14}, [=](double i, double j, double k) {
        const Vec3 q{-0.3 + 1.3 / 8 * i, -1.04 + 0.16 * j, -1.04 + 0.16 * k};
        return Vec3{q.x, std::cos(a) * q.y - std::sin(a) * q.z, std::sin(a) * q.y + std::cos(a) * q.z};
    }, f));
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    const auto field = make_field(to_point_set(mb), fp);
    const double iso = 0.6, tol = 0.01;
    FieldProjectParams p;
    p.seed_tolerance = tol;
    const GraphRun r = run_graph(mb, iso, 2, field.get(), 2, p);
    const GraphRun naive = run_graph(mb, iso, 2, nullptr, 1);
    CHECK(r.newton.converged >= r.newton.input * 99 / 100);

    // for every point of block 0 in the overlap, the nearest point of block 1 (within one coarse
    // cell): the distance of p to q's tangent plane, less what the curvature of a surface through q
    // explains (|p - q|^2 / R with R >= 0.25 here), must be within both points' tolerances
    auto seam = [&](const std::vector<Vec3>& pos, const std::vector<Vec3>& nrm, const std::vector<std::uint32_t>& blk,
                    const std::vector<double>& diag) {
        double worst = 0;
        std::size_t pairs = 0;
        for (std::size_t i = 0; i < pos.size(); ++i) {
            if (blk[i] != 0 || std::abs(pos[i].x) > 0.28) continue;
            double best = 1e9;
            std::size_t bj = 0;
            for (std::size_t j = 0; j < pos.size(); ++j)
                if (blk[j] == 1) {
                    const Vec3 d = pos[j] - pos[i];
                    if (dot(d, d) < best) best = dot(d, d), bj = j;
                }
            if (best > 0.16 * 0.16) continue;
            ++pairs;
            const double off = std::abs(dot(pos[i] - pos[bj], nrm[bj])) - best / 0.25;
            worst = std::max(worst, off / (tol * (diag[i] + diag[bj])));
        }
        return std::pair{worst, pairs};
    };
    std::vector<Vec3> pp, pn, sp, sn;
    std::vector<double> pd, sd;
    for (const auto& q : r.out.points) pp.push_back(at(q)), pn.push_back(normal_of(q));
    // the points' cell diagonals: 0.1 sqrt 3 in block 0, the rotated block's cells are 0.1625 x 0.16 x 0.16
    for (auto b : r.out.block) pd.push_back(b == 0 ? 0.1 * std::sqrt(3.0) : std::sqrt(0.1625 * 0.1625 + 2 * 0.16 * 0.16));
    std::vector<std::uint32_t> sb;
    for (const auto& s : naive.out.seeds) sp.push_back(at(s)), sn.push_back(normal_of(s)), sb.push_back(s.block), sd.push_back(s.cell_diagonal);
    const auto [projected, np] = seam(pp, pn, r.out.block, pd);
    const auto [unprojected, ns] = seam(sp, sn, sb, sd);
    INFO("seam measure (1 = the tolerances): projected " << projected << ", unprojected " << unprojected);
    CHECK(np > 100);
    CHECK(ns > 100);
    CHECK(projected <= 1.0);   // on one surface within the Newton tolerance
    CHECK(unprojected > 1.0);  // the per-block marching-cubes surfaces are not (the oracle can fail)
}

TEST_CASE("the multiblock graph gives identical bytes for any thread count", "[multiblock-graph]") {
    Multiblock mb = sphere_block(10);
    mb.blocks.push_back(sphere_block(7, -0.8, 0.9).blocks[0]);
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    const auto field = make_field(to_point_set(mb), fp);
    const GraphRun one = run_graph(mb, 0.55, 3, field.get(), 1);
    for (int t : {2, 4}) {
        const GraphRun more = run_graph(mb, 0.55, 3, field.get(), t);
        REQUIRE(more.out.points.size() == one.out.points.size());
        CHECK(std::memcmp(more.out.points.data(), one.out.points.data(), one.out.points.size() * sizeof(PointRecord)) == 0);
        CHECK(more.out.block == one.out.block);
    }
    std::size_t in1 = 0;
    for (auto b : one.out.block) in1 += b == 1;
    CHECK(in1 > 0);
    CHECK(in1 < one.out.block.size());
}

TEST_CASE("seed streams and point streams with block ids round-trip through the pipe endpoints", "[multiblock-graph]") {
    const Multiblock mb = sphere_block(8);
    const GraphRun seeds = run_graph(mb, 0.6, 2, nullptr, 1);
    REQUIRE(!seeds.out.seeds.empty());
    std::FILE* f = std::tmpfile();
    REQUIRE(f);
    {
        StreamSink sink(f, "tmp", RecordKind::seed, StreamMeta{});
        Batch b;
        b.kind = RecordKind::seed;
        b.seeds = seeds.out.seeds;
        sink.consume(std::move(b));
        sink.finish();
    }
    std::rewind(f);
    {
        StreamReader r(f, "tmp");
        CHECK(r.kind() == RecordKind::seed);
        CHECK(r.record_bytes() == 40);
        r.read_meta();
        StreamSource src(r);
        auto b = src.next();
        REQUIRE(b);
        REQUIRE(b->seeds.size() == seeds.out.seeds.size());
        CHECK(std::memcmp(b->seeds.data(), seeds.out.seeds.data(), b->seeds.size() * sizeof(SeedRecord)) == 0);
        CHECK(!src.next());
    }
    std::fclose(f);

    const SphereDistance field;
    const GraphRun pts = run_graph(mb, 0.6, 2, &field, 1);
    f = std::tmpfile();
    {
        StreamSink sink(f, "tmp", RecordKind::point, StreamMeta{}, /*compress=*/true, /*with_blocks=*/true);
        Batch b;
        b.kind = RecordKind::point;
        b.points = pts.out.points;
        b.point_block.assign(b.points.size(), 0);
        for (std::size_t i = 0; i < b.point_block.size(); ++i) b.point_block[i] = static_cast<std::uint32_t>(i * 2654435761u);
        const auto blocks = b.point_block;
        sink.consume(std::move(b));
        Batch bad;
        bad.kind = RecordKind::point;
        bad.points.resize(3);
        CHECK_THROWS_AS(sink.consume(std::move(bad)), FormatError);  // points without their block ids
        sink.finish();
        std::rewind(f);
        StreamReader r(f, "tmp");
        CHECK(r.has_blocks());
        CHECK(r.record_bytes() == 36);
        r.read_meta();
        StreamSource src(r);
        auto got = src.next();
        REQUIRE(got);
        REQUIRE(got->points.size() == pts.out.points.size());
        CHECK(std::memcmp(got->points.data(), pts.out.points.data(), got->points.size() * sizeof(PointRecord)) == 0);
        CHECK(got->point_block == blocks);
    }
    std::fclose(f);
}

TEST_CASE("re-projecting points that carry block ids keeps the ids of the points that stay", "[multiblock-graph]") {
    const SphereDistance f;
    Batch b;
    b.kind = RecordKind::point;
    for (int i = 0; i < 5; ++i) {
        PointRecord p{};
        p.pos[0] = i == 2 ? 0.0f : 0.3f + 0.1f * static_cast<float>(i);  // point 2 sits where the gradient vanishes
        b.points.push_back(p);
        b.point_block.push_back(static_cast<std::uint32_t>(10 + i));
    }
    FieldProjectStage stage(f, 0.5);
    stage.process(b);
    REQUIRE(b.points.size() == 4);
    CHECK(b.point_block == std::vector<std::uint32_t>{10, 11, 13, 14});
}
