// The footprint spool (stream/footprint_spool.hpp) alone: footprints round-trip through the
// unlinked file in any append split and any read range (ranges that are not page-aligned, across
// pages, empty); ranges past the end are IoErrors naming the spool.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <vector>

#include "kernels/errors.hpp"
#include "stream/footprint_spool.hpp"

using namespace meshless;

namespace {

std::vector<EwaFootprint> numbered(std::size_t n, std::size_t from) {
    std::vector<EwaFootprint> v(n);
    for (std::size_t i = 0; i < n; ++i) {
        EwaFootprint& f = v[i];
        std::memset(&f, 0, sizeof f);
        f.sx = static_cast<float>(from + i);
        f.depth = 0.5f * static_cast<float>(from + i);
        f.x0 = static_cast<std::uint16_t>((from + i) & 0xFFFF);
        f.base = static_cast<std::uint32_t>(from + i) * 2654435761u;
    }
    return v;
}

}  // namespace

TEST_CASE("FootprintSpool: read gives the appended footprints", "[stream][splat]") {
    FootprintSpool spool("test-footprints");
    const std::size_t n = 10000;  // 600,000 bytes: ~147 pages
    std::vector<EwaFootprint> all;
    for (std::size_t first = 0; first < n; first += 777) {
        const std::vector<EwaFootprint> part = numbered(std::min<std::size_t>(777, n - first), first);
        spool.append(part);
        all.insert(all.end(), part.begin(), part.end());
    }
    spool.flush();
    REQUIRE(spool.size() == n);
    for (std::uint64_t first : {0ull, 1ull, 68ull, 69ull, 4095ull, 9999ull}) {
        for (std::uint64_t count : {0ull, 1ull, 137ull, 5000ull}) {
            if (first + count > n) continue;
            INFO("first " << first << " count " << count);
            std::vector<EwaFootprint> got(count);
            spool.read(first, got);
            if (count == 0) continue;
            CHECK(std::memcmp(got.data(), all.data() + first, count * sizeof(EwaFootprint)) == 0);
            CHECK(got.back().sx == static_cast<float>(first + count - 1));
        }
    }
    std::vector<EwaFootprint> two(2);
    CHECK_THROWS_WITH(spool.read(n - 1, two), Catch::Contains("splat footprint spool (deleted temporary file): it holds 10000"));
    CHECK_THROWS_AS(spool.read(n, std::span(two).first(1)), IoError);
}
