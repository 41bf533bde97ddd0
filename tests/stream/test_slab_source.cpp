// Slab streaming (stream/slab_source.hpp) against the in-memory paradigm (C) run: identical
// points and samples, in the same order, for chunk sizes from one cell slab to the whole volume
// and any thread count; recycled chunk buffers; degenerate grids. Also the runner's CPU count
// (stream/available_cpus.hpp).
#include <unistd.h>

#include <catch2/catch.hpp>

#include <sched.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "kernels/analytic_volumes.hpp"
#include "stream/available_cpus.hpp"
#include "stream/available_memory.hpp"
#include "stream/generate_project_stage.hpp"
#include "stream/generate_stage.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"
#include "stream/runner.hpp"
#include "stream/slab_source.hpp"

using namespace meshless;

namespace {

std::vector<PointRecord> in_memory(const Volume& v, double iso, int threads, SamplingStats* st = nullptr) {
    CollectSink sink;
    const IsoSplatResult r = run_isosplat(v.view(), iso, Projection::approx, SamplingParams{}, sink, {threads});
    if (st) *st = r.sampling;
    return sink.points;
}

std::vector<PointRecord> slabbed(const Volume& v, double iso, std::size_t chunk_bytes, int threads,
                                 SamplingStats* st = nullptr) {
    auto slices = make_volume_source(v, "test volume");
    SlabSource source(*slices, chunk_bytes);
    GenerateProjectStage stage(VolumeView{nullptr, v.type, v.grid}, iso, SamplingParams{}, Projection::approx);
    const Stage* stages[] = {&stage};
    CollectSink sink;
    run_pipeline(source, stages, sink, {threads});
    if (st) *st = stage.sampling_stats();
    return sink.points;
}

bool same_bytes(const std::vector<PointRecord>& a, const std::vector<PointRecord>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(PointRecord)) == 0;
}

/// A uint8 CT-like volume with a non-cubic shape and a non-trivial origin and spacing.
Volume ct_like() {
    Volume v(GridSpec{{37, 29, 23}, {-3.5, 2.0, 10.25}, {0.7, 0.7, 1.25}}, SampleType::u8);
    for (std::int64_t k = 0; k < 23; ++k)
        for (std::int64_t j = 0; j < 29; ++j)
            for (std::int64_t i = 0; i < 37; ++i) {
                const double r = std::sqrt((i - 18.0) * (i - 18.0) + (j - 14.0) * (j - 14.0) + 2.0 * (k - 11.0) * (k - 11.0));
                v.bytes[static_cast<std::size_t>(v.grid.index(i, j, k))] =
                    static_cast<std::byte>(std::clamp(255.0 - 14.0 * r + 9.0 * std::sin(0.9 * i + 0.4 * j), 0.0, 255.0));
            }
    return v;
}

}  // namespace

TEST_CASE("slab-streamed isosplatting equals the in-memory run, byte for byte", "[slab_source]") {
    const Volume v = ct_like();
    const std::size_t slice = 37 * 29;
    for (double iso : {60.5, 128.5, 200.5}) {
        SamplingStats ref_stats;
        const auto ref = in_memory(v, iso, 1, &ref_stats);
        REQUIRE(!ref.empty());
        for (std::size_t chunk : {std::size_t{1}, 2 * slice, 3 * slice + 5, 8 * slice, std::size_t{1} << 20})
            for (int threads : {1, 2, 3}) {
                SamplingStats st;
                const auto got = slabbed(v, iso, chunk, threads, &st);
                INFO("iso " << iso << " chunk " << chunk << " threads " << threads);
                CHECK(same_bytes(got, ref));
                CHECK(st.active_cells == ref_stats.active_cells);
            }
    }
}

TEST_CASE("slab streaming keeps NaN handling and float volumes identical", "[slab_source]") {
    Volume v = make_analytic_volume(AnalyticField::gyroid, 24);
    float* f = reinterpret_cast<float*>(v.bytes.data());
    for (std::size_t i = 0; i < static_cast<std::size_t>(v.grid.voxel_count()); i += 97) f[i] = std::numeric_limits<float>::quiet_NaN();
    SamplingStats ref_stats, st;
    const auto ref = in_memory(v, 0.1, 1, &ref_stats);
    const auto got = slabbed(v, 0.1, 3 * 24 * 24 * 4, 2, &st);
    CHECK(same_bytes(got, ref));
    CHECK(st.nonfinite_cells == ref_stats.nonfinite_cells);
    CHECK(ref_stats.nonfinite_cells > 0);
}

TEST_CASE("slab streaming through the generate stage gives the in-memory samples", "[slab_source]") {
    const Volume v = ct_like();
    std::vector<SampleRecord> ref;
    SamplingStats s;
    sample_active_cells(v.view(), 100.5, 0, cell_row_count(v.grid), SamplingParams{}, ref, s);
    auto slices = make_volume_source(v, "test volume");
    SlabSource source(*slices, 4 * 37 * 29);
    GenerateStage gen(VolumeView{nullptr, v.type, v.grid}, 100.5);
    const Stage* stages[] = {&gen};
    struct SampleCollect final : Sink {
        PayloadSet takes() const override { return Payload::samples; }
        std::vector<SampleRecord> all;
        std::uint64_t last_seq = 0;
        bool ordered = true;
        void consume(Batch&& b) override {
            ordered = ordered && (all.empty() || b.seq > last_seq);
            last_seq = b.seq;
            CHECK(!b.chunk);  // the stage let go of the chunk
            all.insert(all.end(), b.samples.begin(), b.samples.end());
        }
    } sink;
    run_pipeline(source, stages, sink, {2});
    CHECK(sink.ordered);
    REQUIRE(sink.all.size() == ref.size());
    CHECK(std::memcmp(sink.all.data(), ref.data(), ref.size() * sizeof(SampleRecord)) == 0);
}

TEST_CASE("slab source batches stay within the record cap and cover every cell row once", "[slab_source]") {
    Volume v(GridSpec{{300, 300, 5}}, SampleType::u8);  // 299 cells a row: 219 rows per batch
    auto slices = make_volume_source(v, "flat");
    SlabSource source(*slices, 300 * 300 * 3);
    CHECK(source.slabs_per_chunk() == 2);
    std::int64_t rows = 0;
    while (auto b = source.next()) {
        REQUIRE(b->chunk);
        CHECK((b->cells.k1 - b->cells.k0) * 299 <= static_cast<std::int64_t>(kMaxBatchRecords));
        CHECK(b->cells.k1 <= cell_row_count(b->chunk->samples.grid));
        rows += b->cells.k1 - b->cells.k0;
    }
    CHECK(rows == cell_row_count(v.grid));
    // grids without cells yield no batch
    for (GridSpec g : {GridSpec{{5, 5, 1}}, GridSpec{{1, 5, 5}}, GridSpec{{5, 1, 5}}}) {
        auto s = make_volume_source(Volume(g, SampleType::u8), "degenerate");
        SlabSource src(*s);
        CHECK(!src.next());
    }
}

TEST_CASE("available CPUs: the affinity mask, capped by cgroup quotas", "[runner]") {
    const int n = available_cpus();
    cpu_set_t set;
    CPU_ZERO(&set);
    REQUIRE(sched_getaffinity(0, sizeof set, &set) == 0);
    CHECK(n >= 1);
    CHECK(n <= CPU_COUNT(&set));
    CHECK(cpu_quota_limit("200000 100000") == 2);
    CHECK(cpu_quota_limit("150000 100000") == 2);
    CHECK(cpu_quota_limit("50000 100000") == 1);
    CHECK(cpu_quota_limit("max 100000") == std::nullopt);
    CHECK(cpu_quota_limit("-1 100000") == std::nullopt);
    CHECK(cpu_quota_limit("") == std::nullopt);
    CHECK(cpu_quota_limit("abc 100000") == std::nullopt);
    CHECK(cpu_quota_limit("100000 0") == std::nullopt);
}

TEST_CASE("available memory: physical memory, capped by cgroup limits", "[runner]") {
    const std::uint64_t phys = static_cast<std::uint64_t>(sysconf(_SC_PHYS_PAGES)) * static_cast<std::uint64_t>(sysconf(_SC_PAGE_SIZE));
    const std::uint64_t m = available_memory();
    CHECK(m >= 4096);
    CHECK(m <= phys);
    CHECK(memory_limit_value("1073741824\n") == 1073741824u);
    CHECK(memory_limit_value("9223372036854771712") == 9223372036854771712u);  // v1's "no limit": above any machine
    CHECK(memory_limit_value("max\n") == std::nullopt);
    CHECK(memory_limit_value("") == std::nullopt);
    CHECK(memory_limit_value("-1") == std::nullopt);
    CHECK(memory_limit_value("12abc") == std::nullopt);
    CHECK(memory_limit_value("99999999999999999999999") == std::nullopt);
}

TEST_CASE("RunOptions threads <= 0 runs on the available CPUs with the same bytes", "[runner]") {
    const Volume v = ct_like();
    CHECK(same_bytes(in_memory(v, 128.5, 0), in_memory(v, 128.5, 1)));
}
