// Coloured splats through the streaming sink (stream/splat_sink.hpp) and the point spool
// (stream/point_spool.hpp): block and value colours give the collect-all renderer's bytes for both
// kernels, any batch split and thread count (block ids travel in Batch::point_block and through the
// EWA spool); a spool keeps block ids and the value range; colouring by block without ids fails.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "kernels/errors.hpp"
#include "stream/point_spool.hpp"
#include "stream/runner.hpp"
#include "stream/splat_sink.hpp"

#include "kernels/fibonacci_sphere.hpp"

using namespace meshless;

namespace {

struct Points {
    std::vector<PointRecord> pts;
    std::vector<std::uint32_t> blocks;
};

Points sphere(int n) {
    Points s;
    for (int i = 0; i < n; ++i) {
        s.pts.push_back(test::fibonacci_sphere_point(i, n, 3).rec);
        s.blocks.push_back(static_cast<std::uint32_t>(i % 3));
    }
    return s;
}

/// Batches of `per` points with their block ids (or none).
class VectorSource final : public Source {
public:
    Payload gives() const override { return Payload::points; }
    VectorSource(const Points& p, std::size_t per, bool with_blocks) : p_(p), per_(per), blocks_(with_blocks) {}
    std::optional<Batch> next() override {
        if (at_ >= p_.pts.size()) return std::nullopt;
        Batch b;
        b.seq = seq_++;
        b.kind = RecordKind::point;
        const std::size_t e = std::min(p_.pts.size(), at_ + per_);
        b.points.assign(p_.pts.begin() + static_cast<std::ptrdiff_t>(at_), p_.pts.begin() + static_cast<std::ptrdiff_t>(e));
        if (blocks_)
            b.point_block.assign(p_.blocks.begin() + static_cast<std::ptrdiff_t>(at_), p_.blocks.begin() + static_cast<std::ptrdiff_t>(e));
        at_ = e;
        return b;
    }

private:
    const Points& p_;
    std::size_t per_, at_ = 0;
    bool blocks_;
    std::uint64_t seq_ = 0;
};

Camera cam() {
    Camera c;
    c.width = 120;
    c.height = 90;
    return c;
}

}  // namespace

TEST_CASE("coloured splat sink: same bytes as the collect-all renderer, any split and thread count", "[splat][color]") {
    const Points p = sphere(6000);
    const auto bounds = point_bounds(p.pts);
    for (ColorBy by : {ColorBy::block, ColorBy::value, ColorBy::normal})
        for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
            ShadingParams s;
            s.color_by = by;
            s.value_lo = -3;
            s.value_hi = 3;
            const Image expect = render_splats(p.pts, cam(), k, s, nullptr, bounds, p.blocks);
            for (int threads : {1, 3})
                for (std::size_t per : {std::size_t{777}, std::size_t{100000}}) {
                    INFO("by " << int(by) << " kernel " << int(k) << " threads " << threads << " batch " << per);
                    VectorSource src(p, per, true);
                    SplatSink sink(cam(), k, s, bounds, threads);
                    const Stage* stages[] = {&sink.stage()};
                    run_pipeline(src, stages, sink, {threads});
                    CHECK(sink.image().rgb == expect.rgb);
                }
        }
}

TEST_CASE("coloured splat sink: colouring by block needs the ids", "[splat][color]") {
    const Points p = sphere(500);
    ShadingParams s;
    s.color_by = ColorBy::block;
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        VectorSource src(p, 100, false);
        SplatSink sink(cam(), k, s, point_bounds(p.pts), 2);
        const Stage* stages[] = {&sink.stage()};
        CHECK_THROWS_AS(run_pipeline(src, stages, sink, {2}), FormatError);
    }
    // other colours do not need them
    s.color_by = ColorBy::value;
    VectorSource src(p, 100, false);
    SplatSink sink(cam(), SplatKernel::ewa, s, point_bounds(p.pts), 1);
    run_pipeline(src, {}, sink, {1});
    CHECK(sink.points() == 500);
}

TEST_CASE("point spool: block ids and the value range round trip, a replay spool feeds block colours", "[splat][color]") {
    const Points p = sphere(3000);
    PointSpool spool("test-colors");
    VectorSource src(p, 1000, true);
    run_pipeline(src, {}, spool, {1});
    REQUIRE(spool.has_blocks());
    CHECK(spool.block_count() == 3);
    REQUIRE(spool.value_range().has_value());
    CHECK((*spool.value_range())[0] == Approx(-3).margin(0.01));
    CHECK((*spool.value_range())[1] == Approx(3).margin(0.01));
    std::vector<std::uint32_t> back(3000);
    spool.read_blocks(0, back);
    CHECK(back == p.blocks);
    // replayed through the sink with the spool as its pass-2 input: the renderer's bytes
    ShadingParams s;
    s.color_by = ColorBy::block;
    const auto bounds = point_bounds(p.pts);
    SplatSink sink(cam(), SplatKernel::ewa, s, bounds, 2, &spool);
    PointSpoolSource replay(spool, 512);
    const Stage* stages[] = {&sink.stage()};
    run_pipeline(replay, stages, sink, {2});
    CHECK(sink.image().rgb == render_splats(p.pts, cam(), SplatKernel::ewa, s, nullptr, bounds, p.blocks).rgb);
    // mixing points with and without ids is refused
    PointSpool mixed("test-colors-mixed");
    mixed.append(std::span<const PointRecord>(p.pts.data(), 10), std::span<const std::uint32_t>(p.blocks.data(), 10));
    CHECK_THROWS_AS(mixed.append(std::span<const PointRecord>(p.pts.data(), 10)), FormatError);
    PointSpool plain("test-colors-plain");
    plain.append(std::span<const PointRecord>(p.pts.data(), 10));
    CHECK_FALSE(plain.has_blocks());
    CHECK_THROWS_AS(plain.append(std::span<const PointRecord>(p.pts.data(), 10), std::span<const std::uint32_t>(p.blocks.data(), 10)),
                    FormatError);
}
