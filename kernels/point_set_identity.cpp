#include "kernels/point_set_identity.hpp"

#include <bit>
#include <cinttypes>
#include <cstdio>
#include <cstring>

namespace meshless {
namespace {

constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;

inline std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

inline std::uint64_t bits(double d) { return std::bit_cast<std::uint64_t>(d); }

bool same_bits(const Vec3& a, const Vec3& b) {
    return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z);
}

}  // namespace

bool PointSetIdentity::same_data(const PointSetIdentity& o) const {
    return count == o.count && hash == o.hash && same_bits(bounds[0], o.bounds[0]) && same_bits(bounds[1], o.bounds[1]) &&
           bits(value_range[0]) == bits(o.value_range[0]) && bits(value_range[1]) == bits(o.value_range[1]);
}

PointSetIdentity point_set_identity(const PointSet& points) {
    PointSetIdentity id;
    const std::size_t n = points.pos.size();
    id.count = n;
    std::uint64_t h = kGolden ^ static_cast<std::uint64_t>(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = points.pos[i];
        const double v = i < points.value.size() ? points.value[i] : 0.0;
        h = (h ^ mix(bits(p.x) + kGolden)) * 0x100000001B3ull;
        h = (h ^ mix(bits(p.y) + kGolden)) * 0x100000001B3ull;
        h = (h ^ mix(bits(p.z) + kGolden)) * 0x100000001B3ull;
        h = (h ^ mix(bits(v) + kGolden)) * 0x100000001B3ull;
    }
    id.hash = mix(h);
    if (n > 0) {
        id.bounds = points.bounds();
        if (!points.value.empty()) id.value_range = points.value_range();
    }
    return id;
}

std::string describe_identity(const PointSetIdentity& id) {
    char buf[320];
    std::snprintf(buf, sizeof buf, "%" PRIu64 " points, hash %016" PRIx64 ", bounds (%.9g,%.9g,%.9g)..(%.9g,%.9g,%.9g)",
                  id.count, id.hash, id.bounds[0].x, id.bounds[0].y, id.bounds[0].z, id.bounds[1].x, id.bounds[1].y,
                  id.bounds[1].z);
    return buf;
}

}  // namespace meshless
