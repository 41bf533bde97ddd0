// Fixed-size chunking for the cluster binary tree kernels (dissertation section 6.3): a range of n
// items is cut into chunks of kChunk items whatever the thread count, each chunk is reduced in
// order, and the chunk results are combined in chunk order, so a sum over a cluster has the same
// bits on one thread and on many (floating-point addition is not associative). Ranges of at least
// kParallelItems items run their chunks on oneTBB (the chunking, hence the result, is the same).
// Thread-safety: pure helpers; `f` must be safe to call concurrently on distinct chunks.
#pragma once
#include <cstddef>
#include <vector>

#include <tbb/parallel_for.h>

namespace meshless::chunks {

inline constexpr std::size_t kChunk = 8192;
inline constexpr std::size_t kParallelItems = 65536;

inline std::size_t count(std::size_t n) { return (n + kChunk - 1) / kChunk; }

/// Calls f(chunk, begin, end) for every chunk of [0, n); in parallel when n >= kParallelItems.
template <class F>
void for_each(std::size_t n, F&& f) {
    const std::size_t c = count(n);
    if (n >= kParallelItems) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, c, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t k = r.begin(); k != r.end(); ++k) f(k, k * kChunk, std::min(n, (k + 1) * kChunk));
        });
    } else {
        for (std::size_t k = 0; k < c; ++k) f(k, k * kChunk, std::min(n, (k + 1) * kChunk));
    }
}

/// Reduces [0, n): part = f(begin, end) per chunk, total = combine(total, part) in chunk order.
/// Allocates only when it runs in parallel.
template <class T, class F, class C>
T reduce(std::size_t n, T init, F&& f, C&& combine) {
    if (n < kParallelItems) {
        T total = init;
        for (std::size_t b = 0; b < n; b += kChunk) total = combine(total, f(b, std::min(n, b + kChunk)));
        return total;
    }
    std::vector<T> part(count(n));
    for_each(n, [&](std::size_t k, std::size_t b, std::size_t e) { part[k] = f(b, e); });
    T total = init;
    for (const T& p : part) total = combine(total, p);
    return total;
}

}  // namespace meshless::chunks
