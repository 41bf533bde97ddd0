// The footprint spool (stream/footprint_spool.hpp) alone: footprints round-trip through the memory
// tier and the unlinked file in any append split and any read range (ranges that are not
// page-aligned, across pages, across memory chunks and the tier's end, empty), read whole or
// visited in pieces; ranges past the end are IoErrors naming the spool.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <memory>
#include <span>
#include <string>
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

TEST_CASE("FootprintSpool: a memory tier then the file, read and visited across both", "[stream][splat]") {
    // 2.5 chunks in memory, the rest in the file: reads and visits across chunk ends and the tier's end
    const std::size_t tier = FootprintSpool::kChunk * 5 / 2, n = tier + 30000;
    FootprintSpool spool("test-footprints", std::make_shared<SpoolMemory>(tier * sizeof(EwaFootprint)));
    std::vector<EwaFootprint> all;
    for (std::size_t first = 0; first < n; first += 40000) {
        const std::vector<EwaFootprint> part = numbered(std::min<std::size_t>(40000, n - first), first);
        spool.append(part);
        all.insert(all.end(), part.begin(), part.end());
    }
    spool.flush();
    REQUIRE(spool.size() == n);
    CHECK(spool.in_memory() == tier);
    CHECK(spool.memory_bytes() == tier * sizeof(EwaFootprint));  // two full chunks and a half one
    const std::uint64_t C = FootprintSpool::kChunk;
    for (std::uint64_t first : std::vector<std::uint64_t>{0, C - 5, 2 * C + 1, tier - 3, tier, tier + 17, n - 1}) {
        for (std::uint64_t count : std::vector<std::uint64_t>{0, 1, 10, C + 3}) {
            if (first + count > n) continue;
            INFO("first " << first << " count " << count);
            std::vector<EwaFootprint> got(count);
            spool.read(first, got);
            if (count > 0) CHECK(std::memcmp(got.data(), all.data() + first, count * sizeof(EwaFootprint)) == 0);
            // visit: the same footprints in order, in pieces no longer than a chunk past the tier
            std::vector<EwaFootprint> scratch, seen;
            std::size_t pieces = 0;
            spool.visit(first, count, scratch, [&](std::span<const EwaFootprint> p) {
                ++pieces;
                seen.insert(seen.end(), p.begin(), p.end());
            });
            REQUIRE(seen.size() == count);
            if (count > 0) CHECK(std::memcmp(seen.data(), all.data() + first, count * sizeof(EwaFootprint)) == 0);
            CHECK(pieces <= 4);
        }
    }
    std::vector<EwaFootprint> two(2);
    CHECK_THROWS_WITH(spool.read(n - 1, two), Catch::Contains("it holds " + std::to_string(n)));
    std::vector<EwaFootprint> scratch;
    CHECK_THROWS_AS(spool.visit(n, 1, scratch, [](std::span<const EwaFootprint>) {}), IoError);
}

TEST_CASE("FootprintSpool: without a memory tier everything goes to the file", "[stream][splat]") {
    FootprintSpool spool("test-footprints");
    spool.append(numbered(1000, 0));
    spool.flush();
    CHECK(spool.in_memory() == 0);
    CHECK(spool.memory_bytes() == 0);
    std::vector<EwaFootprint> got(3);
    spool.read(997, got);
    CHECK(got[2].sx == 999.0f);
}

TEST_CASE("FootprintSpool: spools sharing a budget hold no more than it together", "[stream][splat]") {
    // a budget of one and a half chunks for three spools filled in turns: the first takes a chunk,
    // the second the half left, the third nothing; each keeps its footprints in order
    const std::size_t C = FootprintSpool::kChunk;
    auto budget = std::make_shared<SpoolMemory>(C * sizeof(EwaFootprint) * 3 / 2);
    FootprintSpool a("test-footprints", budget), b("test-footprints", budget), c("test-footprints", budget);
    std::vector<std::vector<EwaFootprint>> all(3);
    FootprintSpool* spools[3] = {&a, &b, &c};
    for (std::size_t round = 0; round < 6; ++round)
        for (int s = 0; s < 3; ++s) {
            const auto part = numbered(C / 3, round * C);
            spools[s]->append(part);
            all[static_cast<std::size_t>(s)].insert(all[static_cast<std::size_t>(s)].end(), part.begin(), part.end());
        }
    std::size_t held = 0;
    for (int s = 0; s < 3; ++s) {
        spools[s]->flush();
        held += spools[s]->memory_bytes();
        std::vector<EwaFootprint> got(spools[s]->size());
        spools[s]->read(0, got);
        CHECK(std::memcmp(got.data(), all[static_cast<std::size_t>(s)].data(), got.size() * sizeof(EwaFootprint)) == 0);
    }
    CHECK(held <= C * sizeof(EwaFootprint) * 3 / 2);
    CHECK(held + sizeof(EwaFootprint) > C * sizeof(EwaFootprint) * 3 / 2);  // all of it used
    CHECK(budget->left() < sizeof(EwaFootprint));
    CHECK(a.in_memory() == C);
    CHECK(c.in_memory() == 0);
}
