// The field-query graph pieces (stream/field_query_sources.hpp, field_evaluate_stage.hpp,
// field_sinks.hpp) against an analytic field: positions in source order, batch sizes, values and
// gradients, coverage masking, raster sinks filled in order, identical results for any thread count;
// and the recipes that assemble them (stream/field_queries.hpp).
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "formats/png_reader.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/point_coverage.hpp"
#include "stream/field_evaluate_stage.hpp"
#include "stream/field_queries.hpp"
#include "stream/field_query_sources.hpp"
#include "stream/field_sinks.hpp"
#include "stream/runner.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

/// f = 2x - y + 3z + 1 (exact gradient).
class Linear final : public Field {
public:
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override {
        for (std::size_t i = 0; i < p.size(); ++i) {
            value[i] = 2 * p[i].x - p[i].y + 3 * p[i].z + 1;
            if (!grad.empty()) grad[i] = {2, -1, 3};
        }
    }
    std::array<Vec3, 2> bounds() const override { return {Vec3{0, 0, 0}, Vec3{1, 1, 1}}; }
    std::string name() const override { return "linear"; }
};

struct KeepSink final : Sink {
    PayloadSet takes() const override { return Payload::queries; }
    std::vector<Vec3> at, grad;
    std::vector<double> value;
    std::vector<std::size_t> sizes;
    void consume(Batch&& b) override {
        at.insert(at.end(), b.query.at.begin(), b.query.at.end());
        value.insert(value.end(), b.query.value.begin(), b.query.value.end());
        grad.insert(grad.end(), b.query.grad.begin(), b.query.grad.end());
        sizes.push_back(b.query.at.size());
    }
};

}  // namespace

TEST_CASE("grid raster -> evaluate: every sample, x fastest, exact values, any threads", "[field-graph]") {
    GridSpec g;
    g.dims = {7, 5, 4};
    g.origin = {1, -2, 0.5};
    g.spacing = {0.5, 0.25, 2};
    const Linear f;
    for (int threads : {1, 3}) {
        GridRasterSource src(g, 9);
        FieldEvaluateStage st(f);
        KeepSink sink;
        const Stage* stages[] = {&st};
        run_pipeline(src, stages, sink, {threads});
        REQUIRE(sink.at.size() == 140);
        CHECK(sink.sizes.front() == 9);
        CHECK(sink.sizes.back() == 140 % 9);
        CHECK(sink.grad.empty());
        for (std::int64_t n = 0; n < 140; ++n) {
            const std::int64_t i = n % 7, j = (n / 7) % 5, k = n / 35;
            const Vec3 p{1 + 0.5 * i, -2 + 0.25 * j, 0.5 + 2.0 * k};
            REQUIRE(sink.at[n].x == p.x);
            REQUIRE(sink.at[n].y == p.y);
            REQUIRE(sink.at[n].z == p.z);
            REQUIRE(sink.value[n] == Approx(2 * p.x - p.y + 3 * p.z + 1));
        }
    }
}

TEST_CASE("query list with gradients, coverage masks what the data does not reach", "[field-graph]") {
    const Linear f;
    std::vector<Vec3> at;
    for (int i = 0; i < 100; ++i) at.push_back({i * 0.1, 0, 0});
    const std::vector<Vec3> data = {{0, 0, 0}, {0.1, 0, 0}, {0.2, 0, 0}, {0.3, 0, 0}, {0.4, 0, 0}, {0.5, 0, 0},
                                    {0.6, 0, 0}, {0.7, 0, 0}, {0.8, 0, 0}, {0.9, 0, 0}, {1.0, 0, 0}};
    const PointCoverage cover(data, 1.0);
    QueryListSource src(at, true, 16);
    FieldEvaluateStage st(f, &cover);
    KeepSink sink;
    const Stage* stages[] = {&st};
    run_pipeline(src, stages, sink, {2});
    REQUIRE(sink.value.size() == 100);
    REQUIRE(sink.grad.size() == 100);
    CHECK(sink.value[3] == Approx(1.6));
    CHECK(sink.grad[3].z == 3);
    CHECK(std::isnan(sink.value[99]));  // x = 9.9, far from the data
    CHECK(st.uncovered() > 50);
    CHECK(st.uncovered() < 100);
}

TEST_CASE("plane raster pixels, image and NRRD sinks fill in order and refuse overflow", "[field-graph]") {
    PlaneRaster r;
    r.axis = 1;
    r.at = 0.25;
    r.lo_u = 0;
    r.lo_v = 10;
    r.pixel = 0.5;
    r.width = 4;
    r.height = 3;
    const Vec3 top_left = r.position(0, 0);
    CHECK(top_left.x == 0.25);
    CHECK(top_left.y == 0.25);
    CHECK(top_left.z == 10 + 2.5 * 0.5);  // row 0 is the top (largest z)
    const Linear f;
    PlaneRasterSource src(r, 5);
    FieldEvaluateStage st(f);
    SliceImageSink img(4, 3, Colormap::gray, 0, 100);
    const Stage* stages[] = {&st};
    run_pipeline(src, stages, img, {1});
    // gray ramp: brighter where the value is larger; value grows with z, so the top row is brightest
    CHECK(img.image().at(0, 0)[0] > img.image().at(0, 2)[0]);
    Batch extra;
    extra.kind = RecordKind::query;
    extra.query.at.resize(1);
    extra.query.value.resize(1);
    CHECK_THROWS_WITH(img.consume(std::move(extra)), Catch::Contains("more values"));

    TempDir d("fieldgraph");
    GridSpec g;
    g.dims = {3, 2, 2};
    GridRasterSource gs(g, 5);
    NrrdVolumeSink nrrd(g, (d / "v.nrrd").string(), "test");
    run_pipeline(gs, stages, nrrd, {2});
    const Volume v = read_volume((d / "v.nrrd").string());
    REQUIRE(v.grid.dims == g.dims);
    CHECK(v.view().at(2, 1, 1) == Approx(2 * 2 - 1 + 3 * 1 + 1));
}

TEST_CASE("field-query recipes: probe CSV, slice raster and picture, resample grid, callbacks", "[field-graph]") {
    TempDir d("fieldrecipes");
    PointSet pts;
    for (int i = 0; i < 5; ++i) pts.pos.push_back({0.25 * i, 0.5 * (i % 2), 0.1 * i}), pts.value.push_back(i);
    BuiltField f;
    f.field = std::make_unique<Linear>();
    std::atomic<std::size_t> progressed{0};
    std::size_t evaluated = 0;
    FieldQueryRun run;
    run.threads = 2;
    run.progress = [&](double n) { progressed += static_cast<std::size_t>(n); };  // from the stages' threads
    run.evaluated = [&](const FieldQueryStats& s) { evaluated += s.positions; };

    const FieldQueryStats p = probe_field(f, {{0, 0, 0}, {1, 1, 1}}, (d / "p.csv").string(), run);
    CHECK(p.positions == 2);
    CHECK(p.uncovered == 0);
    std::ifstream csv(d / "p.csv");
    const std::string all((std::istreambuf_iterator<char>(csv)), std::istreambuf_iterator<char>());
    CHECK(all == "x,y,z,value,gx,gy,gz\n0,0,0,1,2,-1,3\n1,1,1,5,2,-1,3\n");

    // the box is 1 x 0.5 in (x, y): 256 x 128 pixels fit 256 x 256
    const PlaneRaster r = slice_raster(pts, 2, 0.2, 256, 256);
    CHECK(r.width == 256);
    CHECK(r.height == 128);
    CHECK(r.pixel == 1.0 / 256);
    SliceRequest sr;
    sr.range = {0, 5};
    sr.near = 0.05;  // the points at z = 0.1, 0.2, 0.3
    sr.output = (d / "s.png").string();
    const SliceResult s = slice_field(f, pts, r, sr, run);
    CHECK(s.queries.positions == 256 * 128);
    CHECK(s.shown == 1);
    CHECK(read_png(sr.output).width == 256);

    const GridSpec g = resample_grid(pts, {5, 3, 2});
    CHECK(g.origin[0] == 0);
    CHECK(g.spacing[0] == Approx(0.25));
    CHECK(g.spacing[1] == Approx(0.25));
    CHECK(g.spacing[2] == Approx(0.4));
    resample_field(f, pts, g, (d / "v.nrrd").string(), run);
    const Volume v = read_volume((d / "v.nrrd").string());
    CHECK(v.view().at(4, 2, 1) == Approx(2 * 1 - 0.5 + 3 * 0.4 + 1));
    CHECK(evaluated == 2 + 256 * 128 + 30);
    CHECK(progressed.load() == evaluated);
}
