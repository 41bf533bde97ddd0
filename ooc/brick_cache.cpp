#include "ooc/brick_cache.hpp"

#include <string>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
std::string human_bytes(std::uint64_t b) {
    const char* units[] = {"", "K", "M", "G", "T"};
    int u = 0;
    std::uint64_t v = b;
    while (u < 4 && v >= 1024 && v % 1024 == 0) {
        v /= 1024;
        ++u;
    }
    if (u == 0 && b >= 1024) {  // not a whole number of KiB: round up to one
        return std::to_string((b + 1023) / 1024) + "K";
    }
    return std::to_string(v) + units[u];
}
}  // namespace

BrickCache::BrickCache(const BrickStore& store, std::uint64_t budget_bytes) : store_(store), budget_(budget_bytes) {
    const std::uint64_t need = store.max_brick_bytes();
    if (budget_bytes < need)
        throw InvalidArgument("--memory " + std::to_string(budget_bytes) + " bytes is smaller than one brick of " + store.path() +
                              "; the minimum is " + std::to_string(need) + " bytes (--memory " + human_bytes(need) + ")");
}

std::shared_ptr<const std::vector<std::byte>> BrickCache::get(std::size_t i) {
    {
        std::lock_guard<std::mutex> lock(mu_);
        auto it = slots_.find(i);
        if (it != slots_.end()) {
            ++stats_.hits;
            lru_.splice(lru_.begin(), lru_, it->second.pos);
            return it->second.data;
        }
        ++stats_.misses;
    }
    // Decompress outside the lock: other threads keep hitting the cache meanwhile.
    auto fresh = std::make_shared<std::vector<std::byte>>();
    store_.read_brick(i, *fresh);
    std::shared_ptr<const std::vector<std::byte>> data = std::move(fresh);

    std::lock_guard<std::mutex> lock(mu_);
    auto it = slots_.find(i);
    if (it != slots_.end()) {  // another thread loaded it meanwhile: share that copy
        lru_.splice(lru_.begin(), lru_, it->second.pos);
        return it->second.data;
    }
    const std::uint64_t size = data->size();
    while (bytes_ + size > budget_ && !lru_.empty()) {
        const std::size_t victim = lru_.back();
        lru_.pop_back();
        auto v = slots_.find(victim);
        bytes_ -= v->second.data->size();
        slots_.erase(v);
        ++stats_.evictions;
    }
    lru_.push_front(i);
    slots_.emplace(i, Slot{data, lru_.begin()});
    bytes_ += size;
    stats_.peak_bytes = std::max(stats_.peak_bytes, bytes_);
    return data;
}

VolumeView BrickCache::view(std::size_t i, const std::vector<std::byte>& bytes) const {
    return VolumeView{bytes.data(), store_.info().type, store_.brick_grid(i)};
}

BrickCacheStats BrickCache::stats() const {
    std::lock_guard<std::mutex> lock(mu_);
    return stats_;
}

}  // namespace meshless
