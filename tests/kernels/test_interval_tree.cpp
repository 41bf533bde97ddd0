// Interval tree and Morton codes against brute force.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "kernels/interval_tree.hpp"
#include "kernels/morton.hpp"

using namespace meshless;

TEST_CASE("interval tree stabbing equals brute force", "[interval-tree]") {
    std::mt19937_64 rng(7);
    for (int trial = 0; trial < 40; ++trial) {
        const int n = trial * 37;
        std::vector<Interval> iv(n);
        std::uniform_real_distribution<double> u(0, 255);
        for (int i = 0; i < n; ++i) {
            double a = std::round(u(rng)), b = std::round(u(rng));  // many shared endpoints
            if (trial % 3 == 0) b = a;                              // degenerate intervals
            iv[i] = {std::min(a, b), std::max(a, b), static_cast<std::uint64_t>(i)};
        }
        const IntervalTree tree(iv);
        CHECK(tree.size() == iv.size());
        for (double v : {-1.0, 0.0, 0.5, 17.0, 100.5, 128.0, 254.5, 255.0, 300.0}) {
            std::vector<std::uint64_t> want;
            for (const auto& i : iv)
                if (i.lo <= v && v <= i.hi) want.push_back(i.id);
            CHECK(tree.stab(v) == want);
        }
    }
}

TEST_CASE("interval tree ignores NaN intervals and handles empty input", "[interval-tree]") {
    const IntervalTree empty(std::vector<Interval>{});
    CHECK(empty.stab(1.0).empty());
    const IntervalTree t(std::vector<Interval>{{0, 1, 5}, {std::nan(""), 2, 6}, {3, 2, 7}});
    CHECK(t.size() == 1);
    CHECK(t.stab(0.5) == std::vector<std::uint64_t>{5});
}

TEST_CASE("Morton codes round trip and order by interleaved bits", "[morton]") {
    std::mt19937 rng(3);
    for (int i = 0; i < 10000; ++i) {
        const std::uint32_t x = rng() & 0x1fffff, y = rng() & 0x1fffff, z = rng() & 0x1fffff;
        const auto m = morton_encode(x, y, z);
        CHECK(morton_decode(m) == std::array<std::uint32_t, 3>{x, y, z});
    }
    CHECK(morton_encode(1, 0, 0) == 1);
    CHECK(morton_encode(0, 1, 0) == 2);
    CHECK(morton_encode(0, 0, 1) == 4);
    CHECK(morton_encode(2, 0, 0) == 8);
    CHECK(morton_encode(1, 1, 1) == 7);
}
