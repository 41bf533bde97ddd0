// The byte-budgeted brick cache (docs/architecture.md: "the one shared mutable object"): decompressed bricks
// of a BrickStore, least-recently-used eviction once the budget (the user's --memory) is exceeded.
// get() is thread-safe; a brick handed out stays valid while the caller holds the shared_ptr, even
// if the cache evicts it (so the true peak is budget + bricks in use by the running threads).
// The cached (evictable) bytes never exceed the budget: peak_bytes in stats() reports their maximum.
// Two threads missing the same brick at once may both decompress it; one copy is kept.
// Throws InvalidArgument when the budget is smaller than one brick (BrickStore::max_brick_bytes()),
// naming the minimum; get() throws what BrickStore::read_brick throws (FormatError on damage).
#pragma once
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "ooc/brick_store.hpp"

namespace meshless {

struct BrickCacheStats {
    std::uint64_t hits = 0, misses = 0, evictions = 0, peak_bytes = 0;
};

class BrickCache {
public:
    BrickCache(const BrickStore& store, std::uint64_t budget_bytes);
    /// Brick i, decompressed (native sample type, brick_grid(i) layout).
    std::shared_ptr<const std::vector<std::byte>> get(std::size_t i);
    /// A view of brick i's voxels over the returned bytes (keep the shared_ptr alive).
    VolumeView view(std::size_t i, const std::vector<std::byte>& bytes) const;
    BrickCacheStats stats() const;
    std::uint64_t budget() const { return budget_; }

private:
    const BrickStore& store_;
    std::uint64_t budget_;
    mutable std::mutex mu_;
    std::list<std::size_t> lru_;  ///< most recent first
    struct Slot {
        std::shared_ptr<const std::vector<std::byte>> data;
        std::list<std::size_t>::iterator pos;
    };
    std::unordered_map<std::size_t, Slot> slots_;
    std::uint64_t bytes_ = 0;
    BrickCacheStats stats_;
};

}  // namespace meshless
