#include "kernels/mpu_fit_cache.hpp"

#include <bit>

namespace meshless {

namespace {

// One 64-bit word into a running hash (the splitmix64 finaliser over the sum: every input bit
// reaches every output bit).
std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    std::uint64_t z = h + v + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

std::uint64_t bytes_of(const MpuFitCache::Fit& f) {
    return sizeof(MpuFitCache::Key) + sizeof(MpuFitCache::Fit) + 32 + f.lambda.size() * sizeof(double);
}

}  // namespace

bool MpuFitCache::Key::operator==(const Key& o) const {
    return c.x == o.c.x && c.y == o.c.y && c.z == o.c.z && half == o.half && count == o.count && h1 == o.h1 && h2 == o.h2;
}

MpuFitCache::Key MpuFitCache::key_of(const Vec3& c, double half, std::span<const Vec3> pos, std::span<const double> value,
                                     std::span<const std::uint32_t> idx) {
    Key k{c, half, static_cast<std::uint32_t>(idx.size()), 0x6A09E667F3BCC908ull, 0xBB67AE8584CAA73Bull};
    for (std::uint32_t i : idx) {
        const std::uint64_t w[4] = {std::bit_cast<std::uint64_t>(pos[i].x), std::bit_cast<std::uint64_t>(pos[i].y),
                                    std::bit_cast<std::uint64_t>(pos[i].z), std::bit_cast<std::uint64_t>(value[i])};
        for (std::uint64_t v : w) {
            k.h1 = mix(k.h1, v);
            k.h2 = mix(k.h2 ^ 0xA54FF53A5F1D36F1ull, std::rotl(v, 29));
        }
    }
    return k;
}

void MpuFitCache::begin(double keep_z, bool falling) {
    keep_z_ = keep_z;
    falling_ = falling;
    kept_.clear();
    bytes_kept_ = 0;
}

const MpuFitCache::Fit* MpuFitCache::find(const Key& key) const {
    const auto it = found_.find(key);
    return it == found_.end() ? nullptr : &it->second;
}

void MpuFitCache::keep(const Key& key, Fit fit) {
    bytes_kept_ += bytes_of(fit);
    kept_.insert_or_assign(key, std::move(fit));
}

void MpuFitCache::clear() {
    std::unordered_map<Key, Fit, Hash>().swap(found_);
    std::unordered_map<Key, Fit, Hash>().swap(kept_);
    bytes_found_ = bytes_kept_ = 0;
}

void MpuFitCache::advance() {
    found_.swap(kept_);
    kept_.clear();
    bytes_found_ = bytes_kept_;
    bytes_kept_ = 0;
}

}  // namespace meshless
