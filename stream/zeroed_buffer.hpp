// A zero-filled buffer of fresh pages: an anonymous mapping, 2 MiB-aligned and advised for
// transparent huge pages, whose every element reads 0 until written. Nothing is written to make
// it zero: the kernel maps a page (and zero-fills it) only when it is first written; a page only
// ever read stays the shared zero page. For the EWA accumulators of the splat sink (4 words of 8
// bytes per pixel: 20 MB at 800x800), which are written only where a splat's fragment is accepted
// and read whole once: a std::vector's value-initialisation wrote all 20 MB first, and a fresh
// page costs its fault and zero-filling however it is touched (on a VM whose host reclaims freed
// guest memory, many times more).
// Move-only. Throws std::bad_alloc when the mapping fails. Thread-safety: as a plain array.
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <new>
#include <utility>

namespace meshless {

template <class T>
class ZeroedBuffer {
public:
    ZeroedBuffer() = default;
    /// n elements, all zero (trivially copyable T whose all-zero bytes mean zero).
    explicit ZeroedBuffer(std::size_t n) {
        if (n == 0) return;
        constexpr std::size_t kHuge = std::size_t{2} << 20;
        if (n > (static_cast<std::size_t>(-1) - 2 * kHuge) / sizeof(T)) throw std::bad_alloc();
        const std::size_t bytes = (n * sizeof(T) + kHuge - 1) / kHuge * kHuge;
        // map a huge page more than needed and unmap the ends, so that the buffer starts on one
        void* m = ::mmap(nullptr, bytes + kHuge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED) throw std::bad_alloc();
        const auto at = reinterpret_cast<std::uintptr_t>(m);
        const std::uintptr_t start = (at + kHuge - 1) / kHuge * kHuge;
        if (start > at) ::munmap(m, start - at);
        if (const std::uintptr_t tail = at + bytes + kHuge - (start + bytes); tail > 0)
            ::munmap(reinterpret_cast<void*>(start + bytes), tail);
        ::madvise(reinterpret_cast<void*>(start), bytes, MADV_HUGEPAGE);  // advisory: failure only costs speed
        data_ = reinterpret_cast<T*>(start);
        size_ = n;
        bytes_ = bytes;
    }
    ~ZeroedBuffer() { release(); }
    ZeroedBuffer(ZeroedBuffer&& o) noexcept
        : data_(std::exchange(o.data_, nullptr)), size_(std::exchange(o.size_, 0)), bytes_(std::exchange(o.bytes_, 0)) {}
    ZeroedBuffer& operator=(ZeroedBuffer&& o) noexcept {
        if (this != &o) {
            release();
            data_ = std::exchange(o.data_, nullptr);
            size_ = std::exchange(o.size_, 0);
            bytes_ = std::exchange(o.bytes_, 0);
        }
        return *this;
    }
    ZeroedBuffer(const ZeroedBuffer&) = delete;
    ZeroedBuffer& operator=(const ZeroedBuffer&) = delete;

    T* data() { return data_; }
    const T* data() const { return data_; }
    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    /// Bytes of address space the buffer holds (its pages are memory only once written).
    std::size_t bytes() const { return bytes_; }

private:
    void release() {
        if (data_) ::munmap(data_, bytes_);
        data_ = nullptr;
        size_ = bytes_ = 0;
    }
    T* data_ = nullptr;
    std::size_t size_ = 0, bytes_ = 0;
};

}  // namespace meshless
