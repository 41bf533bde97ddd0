// Morton (Z-order) codes of 3-D integer coordinates, the on-disk order of bricks and samples
// (dissertation section 3.6: "a Morton-order indexing scheme to perform lookups efficiently on
// disk"). 21 bits per axis (coordinates < 2^21), x in the lowest bit of each triple.
// Pure, constexpr, no allocation.
#pragma once
#include <array>
#include <cstdint>

namespace meshless {

constexpr std::uint64_t morton_spread3(std::uint32_t v) {
    std::uint64_t x = v & 0x1fffffu;
    x = (x | (x << 32)) & 0x1f00000000ffffull;
    x = (x | (x << 16)) & 0x1f0000ff0000ffull;
    x = (x | (x << 8)) & 0x100f00f00f00f00full;
    x = (x | (x << 4)) & 0x10c30c30c30c30c3ull;
    x = (x | (x << 2)) & 0x1249249249249249ull;
    return x;
}

constexpr std::uint32_t morton_compact3(std::uint64_t x) {
    x &= 0x1249249249249249ull;
    x = (x | (x >> 2)) & 0x10c30c30c30c30c3ull;
    x = (x | (x >> 4)) & 0x100f00f00f00f00full;
    x = (x | (x >> 8)) & 0x1f0000ff0000ffull;
    x = (x | (x >> 16)) & 0x1f00000000ffffull;
    x = (x | (x >> 32)) & 0x1fffffull;
    return static_cast<std::uint32_t>(x);
}

/// Interleaves x, y, z (each < 2^21).
constexpr std::uint64_t morton_encode(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return morton_spread3(x) | (morton_spread3(y) << 1) | (morton_spread3(z) << 2);
}

constexpr std::array<std::uint32_t, 3> morton_decode(std::uint64_t m) {
    return {morton_compact3(m), morton_compact3(m >> 1), morton_compact3(m >> 2)};
}

}  // namespace meshless
