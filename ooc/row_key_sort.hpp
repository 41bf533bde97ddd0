// Merges a sample store query's candidate cell-row keys (ooc/sample_store.hpp): the keys of the
// candidate buckets, each bucket ascending, into one ascending list without duplicates (a row with
// cells in several buckets appears once). LSD radix sort over the bits of key_limit - 1 (11-bit
// digits), then deduplication: O(n * ceil(bits / 11)) time, n extra keys of memory.
// Pure; thread-safe on distinct vectors. Precondition: every key < key_limit.
#pragma once
#include <cstdint>
#include <vector>

namespace meshless {

void sort_unique_row_keys(std::vector<std::uint64_t>& keys, std::uint64_t key_limit);

}  // namespace meshless
