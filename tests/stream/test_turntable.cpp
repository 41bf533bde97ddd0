// The streaming turntable (stream/turntable.hpp): each frame, drawn by replaying a point spool
// through the splat sink, is byte-identical to the collect-all renderer's turntable frame
// (SplatRenderer::render at azimuth + 360 i / N, what `meshless splat --turntable` drew before it
// streamed), both kernels, any thread count; frames differ from one another; a splat sink whose
// replay spool does not hold its points refuses to finish.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "stream/point_spool.hpp"
#include "stream/splat_sink.hpp"
#include "stream/turntable.hpp"

using namespace meshless;

namespace {

/// An off-centre ellipsoid (latitude-longitude samples, outward normals) and a small sphere in front
/// of it: the frames change with the azimuth and have occlusions.
std::vector<PointRecord> scene() {
    std::vector<PointRecord> pts;
    auto add = [&](double cx, double cy, double cz, double a, double b, double c, int nlat, float r) {
        for (int i = 0; i < nlat; ++i)
            for (int j = 0; j < 2 * nlat; ++j) {
                const double th = std::numbers::pi * (i + 0.5) / nlat, ph = std::numbers::pi * j / nlat;
                const double d[3] = {std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)};
                PointRecord p{};
                p.pos[0] = float(cx + a * d[0]), p.pos[1] = float(cy + b * d[1]), p.pos[2] = float(cz + c * d[2]);
                const double n[3] = {d[0] / a, d[1] / b, d[2] / c}, len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                for (int k = 0; k < 3; ++k) p.normal[k] = float(n[k] / len);
                p.radius = r;
                pts.push_back(p);
            }
    };
    add(0.2, 0, 0, 1.0, 0.5, 0.3, 90, 0.03f);
    add(-0.2, 0.1, 0.7, 0.2, 0.2, 0.2, 30, 0.02f);
    return pts;
}

}  // namespace

TEST_CASE("turntable: frames identical to the collect-all renderer's, both kernels, any thread count", "[turntable]") {
    const auto pts = scene();
    PointSpool spool;
    spool.append(std::span(pts).first(1000));
    spool.append(std::span(pts).subspan(1000));
    const auto bounds = spool.bounds();
    Camera cam;
    cam.width = 120;
    cam.height = 90;
    cam.azimuth_deg = 20;
    cam.elevation_deg = 10;
    constexpr int kFrames = 5;
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        SplatRenderer ref(cam, ShadingParams{}, point_bounds(pts));
        std::vector<std::vector<std::uint8_t>> want;
        for (int i = 0; i < kFrames; ++i) want.push_back(ref.render(pts, k, cam.azimuth_deg + 360.0 * i / kFrames).rgb);
        for (int i = 1; i < kFrames; ++i) REQUIRE(want[i] != want[0]);  // the comparison can fail
        for (int threads : {1, 2, 3}) {
            INFO("kernel " << int(k) << " threads " << threads);
            int seen = 0;
            const TurntableStats t = render_turntable(spool, bounds, cam, k, ShadingParams{}, kFrames, threads,
                                                      [&](int i, const Image& img) {
                                                          CHECK(i == seen++);
                                                          CHECK(img.rgb == want[static_cast<std::size_t>(i)]);
                                                      });
            CHECK(seen == kFrames);
            CHECK(t.frames == kFrames);
            CHECK(t.min_seconds <= t.mean_seconds);
            CHECK(t.mean_seconds <= t.max_seconds);
        }
    }
}

TEST_CASE("splat sink: a replay spool that does not hold the sink's points is refused", "[turntable]") {
    const auto pts = scene();
    PointSpool spool;
    spool.append(std::span(pts).first(100));
    SplatSink sink(Camera{}, SplatKernel::ewa, ShadingParams{}, spool.bounds(), 1, &spool);
    Batch b;
    b.kind = RecordKind::point;
    b.points.assign(pts.begin(), pts.begin() + 50);
    sink.consume(std::move(b));
    CHECK_THROWS_AS(sink.finish(), std::logic_error);
}
