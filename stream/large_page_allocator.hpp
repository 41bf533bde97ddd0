// An allocator for the large per-pixel buffers of the splat sink (keys, EWA accumulators: 5 and
// 20 MB per thread at 800x800): blocks of 2 MiB or more are 2 MiB-aligned and advised for
// transparent huge pages (madvise MADV_HUGEPAGE, a hint the kernel may ignore), so that filling a
// fresh buffer takes a few huge-page faults instead of thousands of 4 KiB ones (costly under a
// hypervisor, and paid once per thread per picture). Smaller blocks come from std::allocator.
// Throws std::bad_alloc. Thread-safe (stateless).
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

namespace meshless {

template <class T>
struct LargePageAllocator {
    using value_type = T;
    static constexpr std::size_t kHugePage = std::size_t{2} << 20;

    LargePageAllocator() = default;
    template <class U>
    LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n * sizeof(T) < kHugePage) return std::allocator<T>{}.allocate(n);
        if (n > static_cast<std::size_t>(-1) / sizeof(T) - kHugePage) throw std::bad_alloc();
        const std::size_t bytes = rounded(n);
        void* p = std::aligned_alloc(kHugePage, bytes);
        if (!p) throw std::bad_alloc();
        ::madvise(p, bytes, MADV_HUGEPAGE);  // advisory: failure only costs speed
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) < kHugePage) std::allocator<T>{}.deallocate(p, n);
        else std::free(p);
    }
    friend bool operator==(const LargePageAllocator&, const LargePageAllocator&) { return true; }

private:
    static std::size_t rounded(std::size_t n) { return (n * sizeof(T) + kHugePage - 1) / kHugePage * kHugePage; }
};

/// A vector whose storage, when large, sits on huge pages.
template <class T>
using LargeBuffer = std::vector<T, LargePageAllocator<T>>;

}  // namespace meshless
