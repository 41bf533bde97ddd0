// A point store's isosurface shared out across ranks by its data (stream/scattered_store_ranks.hpp),
// ranks as threads joined by the in-memory channel: each rank's stencil layers contiguous and every
// layer dealt once; the merged points equal the single-process run's for 1-4 ranks, several budgets
// and thread counts, with --dedup on rank 0's side; each rank loads fewer than all the points (the
// per-rank memory the MPI run saves), and rank 0 gathers the ranks' figures.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <thread>

#include "kernels/marching_stencils.hpp"
#include "ooc/point_store_writer.hpp"
#include "stream/scattered_store_ranks.hpp"

#include "stream/collect_points.hpp"
#include "stream/hub_channel.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::Hub;
using meshless::test::HubChannel;
using Collect = meshless::test::CollectPoints;

namespace {

/// n points uniform in the unit cube, value the distance to (0.5, 0.5, 0.45) with a ripple, as a store.
std::string make_store(const std::filesystem::path& dir, std::size_t n) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<double> xyzv;
    for (std::size_t i = 0; i < n; ++i) {
        const double x = u(rng), y = u(rng), z = u(rng);
        xyzv.insert(xyzv.end(), {x, y, z, std::hypot(x - 0.5, y - 0.5, z - 0.45) + 0.05 * std::sin(9 * x)});
    }
    const std::string path = (dir / "u.mlc").string();
    PointStoreParams p;
    p.brick_points = 256;
    convert_points_to_point_store(
        [&](const std::function<void(std::span<const double>)>& chunk) {
            chunk(xyzv);
            PointChunkTotals t;
            t.points = n;
            t.value_name = "value";
            return t;
        },
        "u", path, p);
    return path;
}

bool same_points(const std::vector<PointRecord>& a, const std::vector<PointRecord>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(PointRecord)) == 0;
}

struct Setup {
    FieldParams fp;
    FieldProjectParams np;
    ScatteredStoreParams sp;
    Setup() {
        fp.kind = FieldKind::mpu;
        np.seed_max_travel = 0.5;  // (half a cell diagonal: slabs reach less far, so the points make several)
    }
};

/// Runs every rank of `ranks` as a thread over the in-memory channel, lattice parameter n (rank r with
/// 1 + r % 2 threads when `mixed`, else one); rank 0 into `out`. Rethrows the first rank's error.
std::vector<StoreRankResult> run_ranks(const PointStore& store, const ScatteredStorePlan& plan, const Setup& s,
                                       const ScatteredStoreParams& sp, double iso, int n, double dedup, int ranks, bool mixed, Sink& out) {
    Hub hub(ranks, 2);
    std::vector<HubChannel> ch;
    for (int r = 0; r < ranks; ++r) ch.emplace_back(hub, r);
    std::vector<StoreRankResult> res(static_cast<std::size_t>(ranks));
    std::vector<std::exception_ptr> err(static_cast<std::size_t>(ranks));
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks; ++r)
        threads.emplace_back([&, r] {
            try {
                res[static_cast<std::size_t>(r)] = run_scattered_store_rank(store, plan, s.fp, sp, iso, n, s.np, dedup, r, ranks,
                                                                            ch[static_cast<std::size_t>(r)], r == 0 ? &out : nullptr,
                                                                            {mixed ? 1 + r % 2 : 1});
            } catch (...) {
                err[static_cast<std::size_t>(r)] = std::current_exception();
            }
        });
    for (auto& t : threads) t.join();
    for (auto& e : err)
        if (e) std::rethrow_exception(e);
    return res;
}

}  // namespace

TEST_CASE("store layers of ranks: contiguous, in rank order, every layer once, the largest load least", "[stream][store_ranks]") {
    test::TempDir dir("store-ranks-layers");
    const auto store = PointStore::open(make_store(dir.path, 60000));
    const ScatteredStorePlan plan = plan_scattered_store(*store, "u", BinningGridParams{}, {});
    const std::int64_t layers = StencilGrid(plan.grid.dims).count[2];
    REQUIRE(layers >= 8);
    const Setup s;
    const double reach = store_slab_reach(plan, s.fp, s.np);
    REQUIRE(reach > 0);
    for (int ranks = 1; ranks <= 6; ++ranks) {
        INFO(ranks << " ranks of " << layers << " layers");
        std::int64_t next = 0;
        std::uint64_t most = 0, most_even = 0;
        for (int r = 0; r < ranks; ++r) {
            const auto l = store_layers_of_rank(plan, r, ranks, reach);
            CHECK(l[0] == next);
            CHECK(l[1] > l[0]);  // (fewer ranks than layers: every rank works)
            next = l[1];
            most = std::max(most, store_layers_loaded(plan, l[0], l[1], reach));
            // oracle: the same number of layers a rank
            const std::int64_t e0 = layers * r / ranks, e1 = layers * (r + 1) / ranks;
            most_even = std::max(most_even, store_layers_loaded(plan, e0, e1, reach));
        }
        CHECK(next == layers);
        CHECK(most <= most_even);
        // brute force over the cuts of two ranks: none loads less at its largest
        if (ranks == 2) {
            std::uint64_t best = UINT64_MAX;
            for (std::int64_t c = 1; c < layers; ++c)
                best = std::min(best, std::max(store_layers_loaded(plan, 0, c, reach), store_layers_loaded(plan, c, layers, reach)));
            CHECK(most == best);
        }
    }
    // the loads: a range loads at least its own layers' points, more with its halos, all with one range
    CHECK(store_layers_loaded(plan, 0, layers, reach) == plan.frame.points);
    CHECK(store_layers_loaded(plan, 3, 3, reach) == 0);
    CHECK(store_layers_loaded(plan, 0, 1, reach) < store_layers_loaded(plan, 0, 2, reach));
    // more ranks than layers: some ranks get none, still every layer once, in order
    std::int64_t total = 0, at = 0;
    for (int r = 0; r < static_cast<int>(layers) + 3; ++r) {
        const auto l = store_layers_of_rank(plan, r, static_cast<int>(layers) + 3, reach);
        CHECK(l[0] == at);
        at = l[1];
        total += l[1] - l[0];
    }
    CHECK(total == layers);
    CHECK_THROWS_AS(store_layers_of_rank(plan, 2, 2, reach), std::invalid_argument);
}

TEST_CASE("store ranks: the single-process points for 1-4 ranks, any budget and threads, each rank loading part", "[stream][store_ranks]") {
    test::TempDir dir("store-ranks");
#ifdef MESHLESS_SANITIZED  // (instrumented, a run of 80,000 points takes minutes: fewer points and cases)
    const std::size_t n = 20000;
#else
    const std::size_t n = 80000;
#endif
    const auto store = PointStore::open(make_store(dir.path, n));
    const ScatteredStorePlan plan = plan_scattered_store(*store, "u", BinningGridParams{}, {});
    const Setup s;
    const double iso = 0.3;
    struct Case {
        int ranks;
        std::uint64_t memory;
        double dedup;
    };
    // (72 MiB: several slabs a rank)
#ifdef MESHLESS_SANITIZED
    const Case cases[] = {{2, 1ull << 30, 0}, {3, 1ull << 30, 0.5}};
#else
    const Case cases[] = {{1, 1ull << 30, 0}, {2, 72ull << 20, 0}, {3, 1ull << 30, 0.5}, {4, 72ull << 20, 0}};
#endif
    std::vector<PointRecord> wants[2];
    ScatteredIsosurfaceStats ones[2];
    for (const Case& c : cases) {
        const int ranks = c.ranks;
        const double dedup = c.dedup;
        const std::uint64_t memory = c.memory;
        const int d = dedup > 0;
        if (wants[d].empty()) {
            Collect want;
            ones[d] = run_scattered_store_isosurface(*store, plan, s.fp, s.sp, iso, 3, s.np, dedup, want, {2});
            wants[d] = std::move(want.points);
            REQUIRE(wants[d].size() > n / 4);
        }
        const ScatteredIsosurfaceStats& one = ones[d];
        {
            {
                INFO("dedup " << dedup << ", " << ranks << " ranks, memory " << memory);
                Collect got;
                ScatteredStoreParams sp = s.sp;
                sp.memory_bytes = memory;
                const std::vector<StoreRankResult> res = run_ranks(*store, plan, s, sp, iso, 3, dedup, ranks, true, got);
                CHECK(got.finished);
                CHECK(same_points(got.points, wants[d]));
                // each rank loads only the points its layers and their halos need
                std::uint64_t seeds = 0;
                for (int r = 0; r < ranks; ++r) {
                    const StoreRankResult& q = res[static_cast<std::size_t>(r)];
                    seeds += static_cast<std::uint64_t>(q.stats.newton.input);
                    // (at 80,000 points the halos are a good part of a layer: the end ranks, with one halo, load
                    // little more than half the points with 4 ranks; the share falls as the points grow)
                    if (n >= 80000 && ranks >= 3) CHECK(q.report.most_loaded < n);
                    if (ranks == 4 && (r == 0 || r == 3)) CHECK(q.report.most_loaded < 7 * n / 10);
                }
                CHECK(seeds == static_cast<std::uint64_t>(one.newton.input));
                if (dedup > 0) CHECK(res[0].stats.dedup_removed == one.dedup_removed);
            }
        }
    }
}

TEST_CASE("store ranks: more ranks than stencil layers, the ranks without layers send nothing and the bytes hold", "[stream][store_ranks]") {
    test::TempDir dir("store-ranks-many");
    const auto store = PointStore::open(make_store(dir.path, 4000));
    const ScatteredStorePlan plan = plan_scattered_store(*store, "u", BinningGridParams{}, {});
    const int ranks = static_cast<int>(StencilGrid(plan.grid.dims).count[2]) + 2;
    const Setup s;
    Collect want;
    (void)run_scattered_store_isosurface(*store, plan, s.fp, s.sp, 0.3, 2, s.np, 0, want, {1});
    REQUIRE(want.points.size() > 1000);
    Collect got;
    const std::vector<StoreRankResult> res = run_ranks(*store, plan, s, s.sp, 0.3, 2, 0, ranks, false, got);
    CHECK(got.finished);
    CHECK(same_points(got.points, want.points));
    int idle = 0;
    for (const StoreRankResult& q : res) idle += q.layers[0] == q.layers[1] && q.report.slabs == 0;
    CHECK(idle >= 2);
}

TEST_CASE("store ranks: the ranks' figures summed to rank 0, each rank's own kept at its place", "[stream][store_ranks]") {
    const int ranks = 3;
    std::vector<StoreRankResult> mine(ranks);
    for (int r = 0; r < ranks; ++r) {
        mine[static_cast<std::size_t>(r)].report.slabs = r + 1;
        mine[static_cast<std::size_t>(r)].report.loaded = 100u * static_cast<unsigned>(r + 1);
        mine[static_cast<std::size_t>(r)].report.most_loaded = 10u * static_cast<unsigned>(r + 1);
        mine[static_cast<std::size_t>(r)].report.field.locals = 7;
        mine[static_cast<std::size_t>(r)].report.field.memory_bytes = 1000u - 100u * static_cast<unsigned>(r);
        mine[static_cast<std::size_t>(r)].peak_rss = 5000u + static_cast<unsigned>(r);
        mine[static_cast<std::size_t>(r)].stats.newton.input = 11;
    }
    // the element-wise sum over the ranks, as MpiSession::sum_to_root gives rank 0 (one sum per call)
    std::vector<std::vector<std::vector<std::int64_t>>> sent(ranks);
    for (int r = ranks - 1; r >= 1; --r)
        (void)sum_store_rank_stats(mine[static_cast<std::size_t>(r)], r, ranks, [&, r](const std::vector<std::int64_t>& v) {
            sent[static_cast<std::size_t>(r)].push_back(v);
            return std::vector<std::int64_t>{};
        });
    std::vector<StoreRankShare> shares;
    std::size_t call = 0;
    const StoreRankResult tot = sum_store_rank_stats(mine[0], 0, ranks, [&](const std::vector<std::int64_t>& v) {
        std::vector<std::int64_t> sum = v;
        for (int r = 1; r < ranks; ++r) {
            const auto& s = sent[static_cast<std::size_t>(r)].at(call);
            REQUIRE(s.size() == v.size());
            for (std::size_t i = 0; i < v.size(); ++i) sum[i] += s[i];
        }
        ++call;
        return sum;
    }, &shares);
    CHECK(tot.report.slabs == 6);
    CHECK(tot.report.loaded == 600);
    CHECK(tot.report.most_loaded == 30);
    CHECK(tot.report.field.locals == 21);
    CHECK(tot.report.field.memory_bytes == 1000);
    CHECK(tot.stats.newton.input == 33);
    REQUIRE(shares.size() == 3);
    CHECK(shares[1].most_loaded == 20);
    CHECK(shares[2].peak_rss == 5002);
}
