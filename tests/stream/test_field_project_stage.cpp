// FieldProjectStage (stream/field_project_stage.hpp) through the runner: seeds from a
// RecordVectorSource projected onto analytic and trilinear fields; points on the known isosurface,
// radii passed through, value = iso, normals towards increasing values as ProjectStage writes them,
// drops counted, and identical bytes for any thread count.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "kernels/analytic_volumes.hpp"
#include "kernels/trilinear_field.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"
#include "stream/record_vector_source.hpp"

#include "stream/sphere_distance_field.hpp"

using namespace meshless;

namespace {

using test::SphereDistance;

std::vector<PointRecord> seeds(std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<PointRecord> s;
    for (std::size_t i = 0; i < n; ++i) {
        PointRecord r{};
        for (float& x : r.pos) x = u(rng);
        if (i % 97 == 0) r.pos[0] = r.pos[1] = r.pos[2] = 0;  // flat (|p| has no gradient at 0)
        r.radius = 0.01f + 0.001f * static_cast<float>(i % 7);
        r.value = -1;
        s.push_back(r);
    }
    return s;
}

std::vector<PointRecord> run(const Field& f, double iso, std::vector<PointRecord> in, int threads,
                             FieldNewtonStats* st = nullptr, FieldProjectParams p = {}) {
    RecordVectorSource source(std::move(in), 1000);
    FieldProjectStage stage(f, iso, p);
    CollectSink sink;
    const Stage* stages[] = {&stage};
    run_pipeline(source, stages, sink, {threads});
    if (st) *st = stage.stats();
    return sink.points;
}

}  // namespace

TEST_CASE("FieldProjectStage: points on the sphere, radius through, value = iso, drops counted", "[field-project]") {
    const SphereDistance f;
    const auto in = seeds(20000, 1);
    FieldNewtonStats st;
    FieldProjectParams p;
    p.newton.tolerance = 1e-6;
    const auto out = run(f, 0.6, in, 1, &st, p);
    CHECK(st.input == 20000);
    CHECK(st.flat == (20000 + 96) / 97);
    CHECK(st.dropped() == st.flat);
    REQUIRE(out.size() == static_cast<std::size_t>(st.converged));
    std::size_t j = 0;
    for (std::size_t i = 0; i < in.size(); ++i) {
        if (i % 97 == 0) continue;  // dropped, the others keep their order
        const PointRecord& o = out[j++];
        REQUIRE(o.radius == in[i].radius);
        REQUIRE(o.value == 0.6f);
        const double r = std::sqrt(double(o.pos[0]) * o.pos[0] + double(o.pos[1]) * o.pos[1] + double(o.pos[2]) * o.pos[2]);
        REQUIRE(r == Approx(0.6).margin(1e-6));
        // unit normal pointing to decreasing values (VTK's convention): inward, |p| grows outwards
        const double dn = (o.normal[0] * o.pos[0] + o.normal[1] * o.pos[1] + o.normal[2] * o.pos[2]) / r;
        REQUIRE(dn == Approx(-1.0).margin(1e-5));
    }
}

TEST_CASE("FieldProjectStage: identical bytes for any thread count", "[field-project]") {
    const Volume v = make_analytic_volume(AnalyticField::gyroid, 40);
    const TrilinearField f(v.view());
    const auto in = seeds(30000, 2);
    FieldNewtonStats s1;
    const auto one = run(f, 0.0, in, 1, &s1);
    REQUIRE(one.size() > 20000);
    for (int t : {2, 3, 4}) {
        FieldNewtonStats st;
        const auto many = run(f, 0.0, in, t, &st);
        REQUIRE(many.size() == one.size());
        REQUIRE(std::memcmp(many.data(), one.data(), one.size() * sizeof(PointRecord)) == 0);
        CHECK(st.converged == s1.converged);
        CHECK(st.evaluations == s1.evaluations);
    }
}

TEST_CASE("FieldProjectStage on trilinear samples: on the trilinear surface, normals as ProjectStage's", "[field-project]") {
    const Volume v = make_analytic_volume(AnalyticField::torus, 48);
    const TrilinearField f(v.view());
    const double iso = default_iso(AnalyticField::torus);
    // the samples `meshless generate` would write (cell centres of active cells)
    struct SampleSink final : Sink {
        PayloadSet takes() const override { return Payload::samples; }
        std::vector<SampleRecord> s;
        void consume(Batch&& b) override { s.insert(s.end(), b.samples.begin(), b.samples.end()); }
    } samples;
    run_isosplat(v.view(), iso, Projection::approx, SamplingParams{}, samples, {1}, PipelineShape::samples_only);
    REQUIRE(samples.s.size() > 1000);
    const std::vector<SampleRecord> in = samples.s;

    RecordVectorSource source(samples.s);
    FieldProjectParams p;
    p.limit_to_cell = true;
    p.newton.tolerance = 1e-6;
    FieldProjectStage stage(f, iso, p);
    CollectSink sink;
    const Stage* stages[] = {&stage};
    run_pipeline(source, stages, sink, {2});
    const FieldNewtonStats st = stage.stats();
    CHECK(st.input == static_cast<std::int64_t>(in.size()));
    CHECK(st.converged + st.dropped() == st.input);
    CHECK(st.converged > static_cast<std::int64_t>(0.95 * in.size()));
    REQUIRE(sink.points.size() == static_cast<std::size_t>(st.converged));
    const double h = v.grid.spacing[0];
    std::size_t k = 0;
    for (const PointRecord& o : sink.points) {
        // match the output to its sample (order kept; drops skipped)
        auto dist = [&](const SampleRecord& s) {
            const double dx = o.pos[0] - s.pos[0], dy = o.pos[1] - s.pos[1], dz = o.pos[2] - s.pos[2];
            return std::sqrt(dx * dx + dy * dy + dz * dz);
        };
        while (k < in.size() && dist(in[k]) > 0.5 * std::sqrt(3.0) * h * 1.0001) ++k;
        REQUIRE(k < in.size());
        const SampleRecord& s = in[k++];
        REQUIRE(o.radius == s.radius);
        const Vec3 x{o.pos[0], o.pos[1], o.pos[2]};
        Vec3 g;
        const double val = f.value(x, &g);
        REQUIRE(std::abs(val - iso) <= 1e-6 * norm(g) + 1e-5 * norm(g) * h);  // float positions
        REQUIRE(std::abs(analytic_distance(AnalyticField::torus, iso, x)) < h * h);
        // against the sample's gradient (ProjectStage's normal, VTK's: towards decreasing values)
        const double d = o.normal[0] * s.grad[0] + o.normal[1] * s.grad[1] + o.normal[2] * s.grad[2];
        REQUIRE(d < 0);
    }
}
