// Typed stage graphs (stream/payload.hpp, stream/stage.hpp): the runner checks the declared payloads of
// source -> stages -> sink before it pulls a batch, and every delivered batch against the declaration.
#include <catch2/catch.hpp>

#include "kernels/analytic_volumes.hpp"
#include "stream/cell_row_source.hpp"
#include "stream/generate_stage.hpp"
#include "stream/mesh_sink.hpp"
#include "stream/point_sinks.hpp"
#include "stream/progress_stage.hpp"
#include "stream/project_stage.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/runner.hpp"
#include "stream/tee_sink.hpp"

using namespace meshless;

namespace {

/// A source that counts its pulls (a graph refused at build time pulls nothing).
class CountingCells final : public Source {
public:
    explicit CountingCells(const GridSpec& g) : inner_(g) {}
    std::optional<Batch> next() override {
        ++pulls;
        return inner_.next();
    }
    Payload gives() const override { return inner_.gives(); }
    int pulls = 0;

private:
    CellRowSource inner_;
};

/// A stage that declares points but leaves the samples it is given as they are.
class LyingStage final : public Stage {
public:
    void process(Batch&) const override {}
    PayloadSet takes() const override { return Payload::samples; }
    Payload gives(Payload) const override { return Payload::points; }
};

}  // namespace

TEST_CASE("stage graph: a chain whose payloads do not meet is refused before the first batch", "[stream][graph]") {
    const Volume v = make_analytic_volume(AnalyticField::sphere, 16);
    CountingCells source(v.grid);
    const ProjectStage project(0.5, Projection::approx);
    CollectSink sink;
    const Stage* stages[] = {&project};
    for (int threads : {1, 2}) {
        try {
            run_pipeline(source, stages, sink, {threads});
            FAIL("no GraphError");
        } catch (const GraphError& e) {
            CHECK(std::string(e.what()) == "stage graph: ProjectStage takes samples, CountingCells gives cell rows");
        }
        CHECK(source.pulls == 0);
    }
    // the sink's end: samples into a mesh writer
    const GenerateStage generate(v.view(), 0.5);
    MeshWeldSink mesh;
    const Stage* gen[] = {&generate};
    CHECK_THROWS_WITH(run_pipeline(source, gen, mesh), "stage graph: MeshWeldSink takes mesh pieces, GenerateStage gives samples");
    CHECK(source.pulls == 0);
}

TEST_CASE("stage graph: check_graph follows the payload through the stages, pass-through stages keep it", "[stream][graph]") {
    const Volume v = make_analytic_volume(AnalyticField::sphere, 16);
    CellRowSource source(v.grid);
    const GenerateStage generate(v.view(), 0.5);
    const ProjectStage project(0.5, Projection::approx);
    const ProgressStage progress(nullptr);
    CollectSink points;
    const Stage* chain[] = {&progress, &generate, &progress, &project, &progress};
    CHECK(check_graph(source, chain, points) == Payload::points);
    CollectSink other;
    TeeSink both(points, other);
    CHECK(check_graph(source, chain, both) == Payload::points);
    // a tee of a point sink and a mesh sink takes nothing
    MeshWeldSink mesh;
    TeeSink mixed(points, mesh);
    CHECK(mixed.takes().empty());
    CHECK_THROWS_AS(check_graph(source, chain, mixed), GraphError);
    CHECK(payload_names({Payload::samples, Payload::points}) == "samples or points");
    CHECK(payload_names(PayloadSet{}) == "nothing");
}

TEST_CASE("stage graph: a stage that delivers another payload than it declared fails at the sink", "[stream][graph]") {
    const LyingStage liar;
    const Stage* stages[] = {&liar};
    CollectSink sink;
    for (int threads : {1, 2}) {
        RecordVectorSource source(std::vector<SampleRecord>(10));
        CHECK_THROWS_WITH(run_pipeline(source, stages, sink, {threads}),
                          "stage graph: LyingStage delivered batch 0 tagged samples, it declared points");
    }
    CHECK(sink.size() == 0);
}

TEST_CASE("stage graph: an empty job runs through the graph its outputs expect", "[stream][graph]") {
    EmptySource none(Payload::mesh);
    MeshWeldSink mesh;
    run_pipeline(none, {}, mesh);
    EmptySource seeds(Payload::seeds);
    CollectSink points;
    CHECK_THROWS_AS(run_pipeline(seeds, {}, points), GraphError);
}
