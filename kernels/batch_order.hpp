// Spatially coherent evaluation order for a batch of field queries: the fields (kernels/
// rbf_grid_field.hpp, kernels/mpu_field.hpp) key each query by the Morton code of the cell of their
// lookup grid it falls in and evaluate the batch cell by cell, so consecutive queries reuse the
// same locals' coefficients from cache; results are written back to each query's own slot, and since every
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

/// The Morton (Z-order) code of cell (i, j, k), 10 bits per axis (30 bits; each index < 1024):
/// keying queries by it instead of by the row-major cell index keeps the cells a run of queries
/// visits close in all three axes, so the locals' data of a cell's neighbours is still cached when
/// the neighbouring cells come (a row-major order revisits a z-neighbour only a whole plane later).
inline std::uint32_t morton_key(std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    auto spread = [](std::uint32_t v) {  // 10 bits -> every third bit
        v &= 0x3FFu;
        v = (v | (v << 16)) & 0x030000FFu;
        v = (v | (v << 8)) & 0x0300F00Fu;
        v = (v | (v << 4)) & 0x030C30C3u;
        v = (v | (v << 2)) & 0x09249249u;
        return v;
    };
    return spread(i) | (spread(j) << 1) | (spread(k) << 2);
}

/// The right shift that brings cell indices below `cells` (per axis) into 10 bits for morton_key().
inline int morton_shift(std::int64_t cells) {
    int s = 0;
    while ((cells - 1) >> s >= 1024) ++s;
    return s;
}

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
/// prefetch(t) is called a few queries ahead of eval(t) (in key order the queries' own slots are
/// visited out of order: it prefetches their input and output).
template <class KeyOf, class Eval, class Prefetch>
void for_each_in_key_order(std::size_t n, KeyOf key_of, Eval eval, Prefetch prefetch) {
    if (n < kBatchOrderMin) {
        for (std::size_t t = 0; t < n; ++t) eval(t);
        return;
    }
    std::vector<std::uint32_t> key(n), order, scratch;
    for (std::size_t t = 0; t < n; ++t) key[t] = key_of(t);
    order_by_key(key, order, scratch);
    constexpr std::size_t kAhead = 8;
    for (std::size_t i = 0; i < n; ++i) {
        if (i + kAhead < n) prefetch(static_cast<std::size_t>(order[i + kAhead]));
        eval(static_cast<std::size_t>(order[i]));
    }
}

template <class KeyOf, class Eval>
void for_each_in_key_order(std::size_t n, KeyOf key_of, Eval eval) {
    for_each_in_key_order(n, key_of, eval, [](std::size_t) {});
}

}  // namespace meshless
