// The set of a sample store query's candidate cell rows (ooc/sample_store.hpp): one bit per
// possible row key (brick count * B^2 bits: 295 KB for the 69 M-cell lung-sized CT with B = 32).
// Inserting the keys of all candidate buckets merges them and removes duplicates (a row with
// cells in several buckets) in O(keys); iterating visits the keys ascending, i.e. bricks in Morton
// order and rows in paradigm (C)'s order, skipping empty 64-row words. No sort, no per-key memory.
// Not thread-safe; one per query.
#pragma once
#include <bit>
#include <cstdint>
#include <vector>

namespace meshless {

class RowSet {
public:
    /// Keys 0 .. limit-1.
    explicit RowSet(std::uint64_t limit) : limit_(limit), words_((limit + 63) / 64, 0) {}
    /// Precondition: key < limit().
    void insert(std::uint64_t key) {
        std::uint64_t& w = words_[key >> 6];
        const std::uint64_t bit = std::uint64_t{1} << (key & 63);
        count_ += (w & bit) == 0;
        w |= bit;
    }
    bool contains(std::uint64_t key) const { return key < limit_ && (words_[key >> 6] >> (key & 63) & 1) != 0; }
    /// The smallest key >= from in the set, or limit() when none.
    std::uint64_t next(std::uint64_t from) const {
        if (from >= limit_) return limit_;
        std::size_t i = from >> 6;
        std::uint64_t w = words_[i] & (~std::uint64_t{0} << (from & 63));
        while (w == 0) {
            if (++i == words_.size()) return limit_;
            w = words_[i];
        }
        return (static_cast<std::uint64_t>(i) << 6) + static_cast<std::uint64_t>(std::countr_zero(w));
    }
    std::uint64_t limit() const { return limit_; }
    /// Distinct keys inserted.
    std::uint64_t size() const { return count_; }

private:
    std::uint64_t limit_;
    std::vector<std::uint64_t> words_;
    std::uint64_t count_ = 0;
};

}  // namespace meshless
