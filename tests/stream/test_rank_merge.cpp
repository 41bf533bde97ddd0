// stream/rank_merge.hpp and stream/isosplat_ranks.hpp in one process: ranks are threads joined by an
// in-memory RankChannel with a bounded window (the MPI channel's contract). Oracles: the
// single-process run_isosplat_bricks bytes for any number of ranks and threads; the bound on
// messages in flight; malformed messages rejected with the rank and unit named.
#include <catch2/catch.hpp>

#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <thread>

#include "kernels/analytic_volumes.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/ooc_test_util.hpp"
#include "stream/isosplat_ranks.hpp"
#include "stream/point_sinks.hpp"
#include "test_paths.hpp"

#include "stream/hub_channel.hpp"

using namespace meshless;
using namespace meshless::test;
using meshless::test::Hub;
using meshless::test::HubChannel;

namespace {

std::string bytes_of(const std::vector<PointRecord>& p) {
    return {reinterpret_cast<const char*>(p.data()), p.size() * sizeof(PointRecord)};
}

}  // namespace

TEST_CASE("ranks streamed to rank 0 give the single-process bytes, in bounded flight", "[rank-merge]") {
    TempDir d("rankmerge");
    const Volume v = make_analytic_volume(AnalyticField::gyroid, 70);
    const std::string path = (d / "g.mlb").string();
    convert_volume(v, path, 16);
    const auto store = BrickStore::open(path);
    const BrickIndex index(*store);
    const double iso = 0.1;
    const std::vector<std::size_t> active = index.active(iso);
    REQUIRE(active.size() > 20);

    BrickCache cache(*store, 64 << 20);
    CollectSink single;
    const IsoSplatResult one = run_isosplat_bricks(*store, cache, active, iso, Projection::approx, SamplingParams{}, single);
    REQUIRE(single.points.size() > 10000);

    for (int ranks : {1, 2, 3, 5}) {
        for (int threads : {1, 2}) {
            Hub hub(ranks, 2);
            CollectSink merged;
            std::vector<IsoSplatResult> res(static_cast<std::size_t>(ranks));
            std::vector<std::thread> workers;
            for (int r = 0; r < ranks; ++r)
                workers.emplace_back([&, r] {
                    HubChannel ch(hub, r);
                    BrickCache own(*store, 64 << 20);
                    res[static_cast<std::size_t>(r)] = run_isosplat_bricks_rank(
                        *store, own, active, r, ranks, iso, Projection::approx, SamplingParams{}, ch, r == 0 ? &merged : nullptr,
                        {threads});
                });
            for (auto& w : workers) w.join();
            INFO(ranks << " ranks, " << threads << " threads");
            CHECK(bytes_of(merged.points) == bytes_of(single.points));
            std::int64_t active_cells = 0, output = 0;
            for (const auto& r : res) {
                active_cells += r.sampling.active_cells;
                output += r.projection.output;
            }
            CHECK(active_cells == one.sampling.active_cells);
            CHECK(output == static_cast<std::int64_t>(single.points.size()));
            for (int r = 1; r < ranks; ++r) CHECK(hub.max_depth[static_cast<std::size_t>(r)] <= 2);
        }
    }
}

TEST_CASE("rank merge: a rank with no units, or units with no batches, still closes them", "[rank-merge]") {
    // 3 units over 4 ranks: rank 3 owns nothing; rank 1's unit produces an empty batch
    Hub hub(4, 1);
    std::thread senders[3];
    for (int r = 1; r <= 3; ++r)
        senders[r - 1] = std::thread([&, r] {
            HubChannel ch(hub, r);
            UnitTags tags;
            RankSendSink s(ch, tags, r, units_of_rank(3, r, 4));
            if (r == 1) {
                tags.push(1);
                Batch b;
                b.kind = RecordKind::point;
                s.consume(std::move(b));
            } else if (r == 2) {
                for (int k = 0; k < 3; ++k) {
                    tags.push(2);
                    Batch b;
                    b.kind = RecordKind::point;
                    b.points.resize(5);
                    for (auto& p : b.points) p.value = static_cast<float>(k);
                    s.consume(std::move(b));
                }
            }
            s.finish();
        });
    HubChannel ch0(hub, 0);
    UnitTags tags;
    CollectSink out;
    RankMergeSink m(ch0, tags, 3, 4, out);
    tags.push(0);
    Batch b;
    b.kind = RecordKind::point;
    b.points.resize(2);
    m.consume(std::move(b));
    m.finish();
    for (auto& t : senders) t.join();
    REQUIRE(out.points.size() == 2 + 15);
    CHECK(out.points[2].value == 0);
    CHECK(out.points[16].value == 2);
    CHECK(m.received_messages() == 2 /* unit 1: data, end */ + 4 /* unit 2: 3 data, end */);
}

TEST_CASE("rank merge: malformed messages name the rank and unit", "[rank-merge]") {
    Hub hub(2, 4);
    HubChannel ch1(hub, 1), ch0(hub, 0);
    SECTION("short message") {
        ch1.send_to_root(std::vector<std::byte>(7));
    }
    SECTION("wrong unit") {
        UnitTags tags;
        RankSendSink s(ch1, tags, 1, {1, 3});
        tags.push(3);
        Batch b;
        b.kind = RecordKind::point;
        s.consume(std::move(b));  // END of unit 1, then unit 3's data
        // drop unit 1's END: rank 0 then reads unit 3's message while waiting for unit 1
        std::vector<std::byte> m;
        ch0.receive_from(1, m);
    }
    SECTION("count disagrees with the size") {
        UnitTags tags;
        RankSendSink s(ch1, tags, 1, {1});
        tags.push(1);
        Batch b;
        b.kind = RecordKind::point;
        b.points.resize(3);
        s.consume(std::move(b));
        std::vector<std::byte> m;
        ch0.receive_from(1, m);
        m.resize(m.size() - 1);
        ch1.send_to_root(std::move(m));
    }
    UnitTags tags;
    CollectSink out;
    RankMergeSink merge(ch0, tags, 2, 2, out);
    CHECK_THROWS_WITH(merge.finish(), Catch::Contains("rank 1, unit 1"));
}
