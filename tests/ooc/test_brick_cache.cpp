// BrickCache: minimum budget, LRU eviction under the byte budget, concurrent get()
// (parse_memory_size, the --memory syntax, is tested with the CLI: tests/cli/test_args.cpp).
#include <catch2/catch.hpp>

#include <thread>

#include "kernels/errors.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc_test_util.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

TEST_CASE("brick cache refuses a budget smaller than one brick, naming the minimum", "[ooc]") {
    TempDir dir("ooc-cache-min");
    const std::string path = (dir / "c.mlb").string();
    convert_volume(random_volume({33, 33, 33}, SampleType::i16), path, 8);
    const auto store = BrickStore::open(path);
    const std::uint64_t one = store->max_brick_bytes();
    CHECK(one == 9 * 9 * 9 * 2);
    CHECK_THROWS_AS(BrickCache(*store, one - 1), InvalidArgument);
    CHECK_THROWS_WITH(BrickCache(*store, one - 1), Catch::Contains(std::to_string(one)));
    CHECK_NOTHROW(BrickCache(*store, one));
}

TEST_CASE("brick cache evicts least recently used bricks and stays within its budget", "[ooc]") {
    TempDir dir("ooc-cache-lru");
    const std::string path = (dir / "c.mlb").string();
    convert_volume(random_volume({33, 33, 33}, SampleType::u8), path, 8);  // 64 bricks of 9^3 bytes
    const auto store = BrickStore::open(path);
    const std::uint64_t one = store->max_brick_bytes();
    BrickCache cache(*store, 3 * one);
    std::vector<std::byte> ref;
    for (std::size_t i : {0, 1, 2}) cache.get(i);
    CHECK(cache.stats().misses == 3);
    cache.get(0);  // hit; 1 is now the least recently used
    CHECK(cache.stats().hits == 1);
    cache.get(3);  // evicts 1
    CHECK(cache.stats().evictions == 1);
    cache.get(0);
    cache.get(2);
    CHECK(cache.stats().hits == 3);
    cache.get(1);  // was evicted: a miss
    CHECK(cache.stats().misses == 5);
    // A long scan keeps the cached bytes within the budget, and every brick is right.
    for (int rep = 0; rep < 2; ++rep)
        for (std::size_t i = 0; i < store->bricks().size(); ++i) {
            const auto d = cache.get(i);
            store->read_brick(i, ref);
            REQUIRE(*d == ref);
            const VolumeView view = cache.view(i, *d);
            CHECK(view.grid == store->brick_grid(i));
        }
    CHECK(cache.stats().peak_bytes <= cache.budget());
    // A brick handed out stays valid after it is evicted.
    const auto held = cache.get(10);
    const auto copy = *held;
    for (std::size_t i = 20; i < 40; ++i) cache.get(i);
    CHECK(*held == copy);
}

TEST_CASE("brick cache: concurrent get() from 4 threads returns identical data", "[ooc]") {
    TempDir dir("ooc-cache-mt");
    const std::string path = (dir / "c.mlb").string();
    convert_volume(random_volume({50, 41, 47}, SampleType::f32), path, 8);
    const auto store = BrickStore::open(path);
    const std::size_t n = store->bricks().size();
    std::vector<std::vector<std::byte>> ref(n);
    for (std::size_t i = 0; i < n; ++i) store->read_brick(i, ref[i]);
    BrickCache cache(*store, 5 * store->max_brick_bytes());
    std::vector<int> bad(4, 0);
    std::vector<std::thread> th;
    for (int t = 0; t < 4; ++t)
        th.emplace_back([&, t] {
            for (int rep = 0; rep < 20; ++rep)
                for (std::size_t q = 0; q < n; ++q) {
                    const std::size_t i = (q * (2 * t + 1) + static_cast<std::size_t>(rep)) % n;
                    if (*cache.get(i) != ref[i]) ++bad[static_cast<std::size_t>(t)];
                }
        });
    for (auto& x : th) x.join();
    CHECK(bad == std::vector<int>(4, 0));
    const auto s = cache.stats();
    CHECK(s.hits + s.misses == 4u * 20u * n);
    CHECK(s.peak_bytes <= cache.budget());
}
