// The zero-filled buffer of fresh pages (stream/zeroed_buffer.hpp) and the accumulator merge that
// leaves its untouched pages alone (SplatFrame::merge_acc).
#include <catch2/catch.hpp>

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <random>
#include <vector>

#include "kernels/splat_rasterizer.hpp"
#include "stream/zeroed_buffer.hpp"

using namespace meshless;

namespace {
/// Bytes of [p, p + bytes) resident in memory (mincore, whole pages).
std::size_t resident_bytes(const void* p, std::size_t bytes) {
    const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
    std::vector<unsigned char> in((bytes + page - 1) / page);
    REQUIRE(::mincore(const_cast<void*>(p), bytes, in.data()) == 0);
    std::size_t n = 0;
    for (unsigned char c : in) n += (c & 1) ? page : 0;
    return n;
}
}  // namespace

TEST_CASE("a zeroed buffer reads zero everywhere and holds memory only where it was written", "[stream][splat]") {
    constexpr std::size_t n = std::size_t{5} << 20;  // 40 MiB of int64
    ZeroedBuffer<std::int64_t> b(n);
    REQUIRE(b.size() == n);
    CHECK(b.bytes() >= n * sizeof(std::int64_t));
    CHECK(reinterpret_cast<std::uintptr_t>(b.data()) % (std::size_t{2} << 20) == 0);
    b.data()[n / 2] = 7;
    // one written word makes at most one huge page resident (checked before any read: mincore
    // counts the zero page that a read maps as resident too)
    CHECK(resident_bytes(b.data(), b.bytes()) <= (std::size_t{2} << 20));
    std::int64_t any = 0;
    for (std::size_t i = 0; i < n; i += 97) any |= i == n / 2 ? 0 : b.data()[i];
    CHECK(any == 0);
    ZeroedBuffer<std::int64_t> moved = std::move(b);
    CHECK(b.empty());
    CHECK(b.data() == nullptr);
    CHECK(moved.data()[n / 2] == 7);
    moved = ZeroedBuffer<std::int64_t>(3);
    CHECK(moved.size() == 3);
    CHECK(moved.data()[2] == 0);
    CHECK(ZeroedBuffer<std::int64_t>(0).empty());
}

TEST_CASE("merging accumulators sums every word and leaves the pages under all-zero runs unwritten", "[stream][splat]") {
    constexpr std::size_t n = 3 * 512 * 512 + 77;  // runs of 512 words and a ragged tail
    std::mt19937_64 rng(5);
    std::vector<std::int64_t> src(n, 0), dst(n), want(n);
    for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<std::int64_t>(rng() % 1000) - 500;
    // non-zero words in some runs only (one at a run's last word, one in the tail), negative included
    for (std::size_t i : {std::size_t{3}, std::size_t{511}, std::size_t{512 * 100 + 7}, n - 1}) src[i] = -static_cast<std::int64_t>(i) - 1;
    for (std::size_t i = 0; i < n; ++i) want[i] = dst[i] + src[i];
    SplatFrame::merge_acc(dst.data(), src.data(), n);
    CHECK(dst == want);

    // into a fresh zeroed buffer: the runs src leaves at zero are never written
    ZeroedBuffer<std::int64_t> fresh(n);
    SplatFrame::merge_acc(fresh.data(), src.data(), n);
    CHECK(resident_bytes(fresh.data(), fresh.bytes()) <= 2 * (std::size_t{2} << 20));  // the first and the last
    for (std::size_t i = 0; i < n; ++i) REQUIRE(fresh.data()[i] == src[i]);
}
