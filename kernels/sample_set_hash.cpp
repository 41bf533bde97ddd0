#include "kernels/sample_set_hash.hpp"

#include <bit>
#include <cmath>

namespace meshless {

namespace {
std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
}
}  // namespace

std::uint64_t sample_set_hash(std::span<const Vec3> pos, std::span<const double> value) {
    std::uint64_t sum = 0;
    const std::size_t n = pos.size() < value.size() ? pos.size() : value.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = pos[i];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(value[i]))) continue;
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (const double d : {p.x, p.y, p.z, value[i]}) h = mix(h ^ std::bit_cast<std::uint64_t>(d + 0.0));  // (+0.0: -0 as 0)
        sum += h;
    }
    return sum == 0 ? 1 : sum;
}

}  // namespace meshless
