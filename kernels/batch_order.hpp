// Spatially coherent evaluation order for a batch of field queries: the fields (kernels/
// rbf_grid_field.hpp, kernels/mpu_field.hpp) key each query by the cell of their lookup grid it
// falls in and evaluate the batch cell by cell, so consecutive queries reuse the same locals'
// coefficients from cache; results are written back to each query's own slot, and since every
// query is evaluated independently of the others the output is bit-identical to any other order.
// order_by_key() is a stable LSD radix sort (two 16-bit passes) of 32-bit keys: O(n + 65536).
// Thread-safety: pure function. Throws std::bad_alloc only.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace meshless {

/// Batches at least this long are evaluated in key order (shorter ones in input order: the
/// histogram passes would cost more than the cache misses they save).
inline constexpr std::size_t kBatchOrderMin = 2048;

/// order = the permutation of 0..key.size()-1 sorting key ascending (ties in input order).
/// scratch is reused between calls.
inline void order_by_key(std::span<const std::uint32_t> key, std::vector<std::uint32_t>& order,
                         std::vector<std::uint32_t>& scratch) {
    const std::size_t n = key.size();
    order.resize(n);
    scratch.resize(n);
    std::vector<std::uint32_t> count(65537);
    for (std::size_t i = 0; i < n; ++i) ++count[(key[i] & 0xFFFFu) + 1];
    for (std::size_t d = 0; d < 65536; ++d) count[d + 1] += count[d];
    for (std::size_t i = 0; i < n; ++i) scratch[count[key[i] & 0xFFFFu]++] = static_cast<std::uint32_t>(i);
    std::fill(count.begin(), count.end(), 0u);
    for (std::size_t i = 0; i < n; ++i) ++count[(key[i] >> 16) + 1];
    for (std::size_t d = 0; d < 65536; ++d) count[d + 1] += count[d];
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t s = scratch[i];
        order[count[key[s] >> 16]++] = s;
    }
}

/// Calls eval(t) once for every query t in [0, n): in ascending key_of(t) order (order_by_key)
/// when n >= kBatchOrderMin, else in index order. The batch evaluation loop of both fields.
template <class KeyOf, class Eval>
void for_each_in_key_order(std::size_t n, KeyOf key_of, Eval eval) {
    if (n < kBatchOrderMin) {
        for (std::size_t t = 0; t < n; ++t) eval(t);
        return;
    }
    std::vector<std::uint32_t> key(n), order, scratch;
    for (std::size_t t = 0; t < n; ++t) key[t] = key_of(t);
    order_by_key(key, order, scratch);
    for (const std::uint32_t t : order) eval(static_cast<std::size_t>(t));
}

}  // namespace meshless
