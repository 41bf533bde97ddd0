// The scattered isosurface over ranks (stream/stencil_ranks.hpp) with the dynamic deal of stencil
// rows (stream/unit_deal.hpp), ranks as threads joined by the in-memory channel: the single-process
// bytes for any number of ranks and threads, a slow rank dealt fewer rows than the others (the deal
// balances), and the dealer's bookkeeping (owners only of dealt units, rows once each, in order);
// the recipe's rank split (stream/scattered_isosurface.hpp run_scattered_isosurface_rank, with
// --dedup) against run_scattered_isosurface, and the sum of the ranks' statistics.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstring>
#include <mutex>
#include <numeric>
#include <random>
#include <thread>

#include "kernels/errors.hpp"
#include "kernels/scattered_binning_grid.hpp"
#include "stream/runner.hpp"
#include "stream/scattered_isosurface.hpp"
#include "stream/stencil_ranks.hpp"
#include "stream/stencil_source.hpp"
#include "stream/unit_deal.hpp"

#include "stream/collect_points.hpp"
#include "stream/hub_channel.hpp"
#include "stream/sphere_distance_field.hpp"

using namespace meshless;
using meshless::test::Hub;
using meshless::test::HubChannel;
using Collect = meshless::test::CollectPoints;

namespace {

/// |p| as the sphere field, each evaluate() call `delay` slower (a rank on a slower machine).
class SlowSphere final : public Field {
public:
    explicit SlowSphere(std::chrono::microseconds delay) : delay_(delay) {}
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override {
        std::this_thread::sleep_for(delay_);
        inner_.evaluate(p, value, grad);
    }
    std::array<Vec3, 2> bounds() const override { return inner_.bounds(); }
    std::string name() const override { return "slow-sphere"; }

private:
    test::SphereDistance inner_;
    std::chrono::microseconds delay_;
};

struct Scene {
    std::vector<Vec3> pos;
    std::vector<double> val;
    BinningGrid g;
    BinnedPoints b;
    Scene() {
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(-1, 1);
        for (int i = 0; i < 6000; ++i) pos.push_back({u(rng), u(rng), u(rng)});
        for (const Vec3& p : pos) val.push_back(norm(p));
        g = make_binning_grid(pos);
        b = bin_points(g, pos);
    }
};

std::string bytes_of(const std::vector<PointRecord>& p) { return {reinterpret_cast<const char*>(p.data()), p.size() * sizeof(PointRecord)}; }

/// Runs `ranks` ranks as threads; rank r evaluates field_of(r). Returns rank 0's result.
StencilRankResult run_ranks(const Scene& s, int ranks, int threads, const std::function<const Field&(int)>& field_of, Collect& out,
                            Hub& hub) {
    const double iso = 0.55;
    FieldProjectParams np;
    np.seed_tolerance = 0.01;
    std::vector<StencilRankResult> res(static_cast<std::size_t>(ranks));
    std::vector<std::thread> workers;
    for (int r = 0; r < ranks; ++r)
        workers.emplace_back([&, r] {
            HubChannel ch(hub, r);
            const StencilInput in{s.g, s.b, s.pos, s.val, field_of(r)};
            res[static_cast<std::size_t>(r)] = run_stencils_rank(in, iso, 2, np, r, ranks, ch, r == 0 ? &out : nullptr, {threads});
        });
    for (auto& w : workers) w.join();
    std::int64_t seeds = 0;
    for (const auto& r : res) seeds += r.seeds.seeds;
    res[0].seeds.seeds = seeds;
    return res[0];
}

}  // namespace

TEST_CASE("unit dealer: units in order, owners only of dealt units, counts per rank", "[stream][scattered][mpi]") {
    UnitDealer d(5, 3);
    CHECK(d.take(2) == std::optional<std::size_t>(0));
    CHECK(d.take(0) == std::optional<std::size_t>(1));
    CHECK(d.take(2) == std::optional<std::size_t>(2));
    CHECK(d.owner(0) == 2);
    CHECK(d.owner(1) == 0);
    CHECK_THROWS_AS(d.owner(3), std::logic_error);
    CHECK(d.take(1) == std::optional<std::size_t>(3));
    CHECK(d.take(1) == std::optional<std::size_t>(4));
    CHECK_FALSE(d.take(0).has_value());
    CHECK(d.dealt_per_rank() == std::vector<std::size_t>{1, 2, 2});
    UnitList l;
    l.push(3);
    CHECK_THROWS_AS(l.push(3), FormatError);  // a unit dealt twice, or out of order
    CHECK(l.at(0) == std::optional<std::size_t>(3));
    CHECK_FALSE(l.at(1).has_value());
}

TEST_CASE("stencil ranks: rows dealt on request give the single-process bytes for any ranks and threads", "[stream][scattered][mpi]") {
    const Scene s;
    const test::SphereDistance f;
    Collect single;
    {
        const double iso = 0.55;
        FieldProjectParams np;
        np.seed_tolerance = 0.01;
        StencilSource src{StencilGrid(s.g.dims)};
        const StencilInput in{s.g, s.b, s.pos, s.val, f};
        const StencilSeedStage seed(in, iso, 2);
        const FieldProjectStage project(f, iso, np);
        const Stage* stages[] = {&seed, &project};
        run_pipeline(src, stages, single, {2});
    }
    REQUIRE(single.points.size() > 2000);
    const StencilGrid sg(s.g.dims);
    const auto rows = static_cast<std::size_t>(sg.count[1] * sg.count[2]);
    for (int ranks : {1, 2, 3, 5})
        for (int threads : {1, 2}) {
            INFO(ranks << " ranks, " << threads << " threads");
            Hub hub(ranks, 2);
            Collect merged;
            const StencilRankResult r0 = run_ranks(s, ranks, threads, [&](int) -> const Field& { return f; }, merged, hub);
            CHECK(bytes_of(merged.points) == bytes_of(single.points));
            REQUIRE(r0.rows_per_rank.size() == static_cast<std::size_t>(ranks));
            CHECK(std::accumulate(r0.rows_per_rank.begin(), r0.rows_per_rank.end(), std::size_t{0}) == rows);
            // every rank but 0 asked once per row it got, and once more to hear that none was left
            CHECK(hub.requests_made == rows - r0.rows_per_rank[0] + static_cast<std::size_t>(ranks - 1));
            for (int r = 1; r < ranks; ++r) CHECK(hub.max_depth[static_cast<std::size_t>(r)] <= 2);
        }
}

TEST_CASE("stencil ranks: a slow rank is dealt fewer rows, the bytes stay the same", "[stream][scattered][mpi]") {
    const Scene s;
    const test::SphereDistance f;
    const SlowSphere slow(std::chrono::milliseconds(20));
    Hub hub_fast(3, 2), hub_slow(3, 2);
    Collect even, uneven;
    (void)run_ranks(s, 3, 1, [&](int) -> const Field& { return f; }, even, hub_fast);
    const StencilRankResult r0 = run_ranks(s, 3, 1, [&](int r) -> const Field& { return r == 2 ? static_cast<const Field&>(slow) : f; },
                                           uneven, hub_slow);
    CHECK(bytes_of(uneven.points) == bytes_of(even.points));
    INFO("rows dealt: " << r0.rows_per_rank[0] << " / " << r0.rows_per_rank[1] << " / " << r0.rows_per_rank[2]);
    // each of the slow rank's rows costs >= 20 ms per field call; the others take the rest
    CHECK(r0.rows_per_rank[2] < r0.rows_per_rank[0]);
    CHECK(r0.rows_per_rank[2] < r0.rows_per_rank[1]);
}

TEST_CASE("scattered isosurface rank split: the single-process bytes (with and without dedup), an empty run, the summed statistics",
          "[stream][scattered][mpi]") {
    const Scene s;
    const test::SphereDistance f;
    PointSet ps;
    ps.pos = s.pos;
    ps.value = s.val;
    ps.blocks.push_back({"scene", {static_cast<std::int64_t>(s.pos.size()), 1, 1}, 0, s.pos.size()});
    ScatteredIsosurfaceInput in = bin_scattered_points(std::move(ps), "scene", "scene", BinningGridParams{}, 0, {});
    FieldProjectParams np;
    np.seed_tolerance = 0.01;
    const double iso = 0.55;
    for (const double dedup : {0.0, 0.5}) {
        Collect single;
        const ScatteredIsosurfaceStats one = run_scattered_isosurface(in, &f, iso, 2, np, dedup, nullptr, single, {2});
        const int ranks = 3;
        Hub hub(ranks, 4);
        Collect merged;
        std::vector<StencilRankResult> res(ranks);
        std::vector<std::thread> workers;
        for (int r = 0; r < ranks; ++r)
            workers.emplace_back([&, r] {
                HubChannel ch(hub, r);
                res[static_cast<std::size_t>(r)] =
                    run_scattered_isosurface_rank(in, &f, iso, 2, np, dedup, r, ranks, &ch, r == 0 ? &merged : nullptr, {1});
            });
        for (auto& w : workers) w.join();
        CHECK(bytes_of(merged.points) == bytes_of(single.points));
        // the sum over the ranks: every counter but the largest stencil (rank 0's)
        std::vector<std::vector<std::int64_t>> sent;
        std::mutex m;
        const auto gather = [&](const std::vector<std::int64_t>& v) {
            const std::lock_guard<std::mutex> lock(m);
            sent.push_back(v);
            return std::vector<std::int64_t>{};
        };
        for (int r = 1; r < ranks; ++r) (void)sum_stencil_rank_stats(res[static_cast<std::size_t>(r)], gather);
        const auto sum_all = [&](const std::vector<std::int64_t>& v) {
            std::vector<std::int64_t> t = v;
            for (const auto& o : sent)
                for (std::size_t i = 0; i < t.size(); ++i) t[i] += o[i];
            return t;
        };
        const StencilRankResult tot = sum_stencil_rank_stats(res[0], sum_all);
        CHECK(tot.seeds.seeds == one.seeds.seeds);
        CHECK(tot.seeds.triangles == one.seeds.triangles);
        CHECK(tot.seeds.max_stencil_points == res[0].seeds.max_stencil_points);
        CHECK(tot.newton.input == one.newton.input);
        CHECK(tot.newton.converged == one.newton.converged);
        CHECK(tot.rows_per_rank == res[0].rows_per_rank);
    }
    // no field (the isovalue outside the data): rank 0 finishes an empty output, no channel needed
    Collect empty;
    const StencilRankResult none = run_scattered_isosurface_rank(in, nullptr, 9, 2, np, 0.5, 0, 2, nullptr, &empty, {1});
    CHECK(empty.points.empty());
    CHECK(none.seeds.seeds == 0);
    CHECK(run_scattered_isosurface_rank(in, nullptr, 9, 2, np, 0, 1, 2, nullptr, nullptr, {1}).seeds.seeds == 0);
}
