// SampleBytes: the byte storage of a Volume, with the parts of std::vector<std::byte>'s interface
// that volumes use (data, size, resize, iteration, indexing, comparison).
//
// It either owns a std::vector<std::byte>, or adopts memory owned by someone else and kept alive
// by a shared owner handle: formats/mapped_file.hpp hands in a private (copy-on-write) file
// mapping this way, so a volume read from a raw or NRRD file costs no read(), no zeroing and no
// copy. Adopted memory must be writable (a private mapping is: writes copy the page, the file is
// never changed). Copying a SampleBytes always copies the bytes into an owned vector (two volumes
// never share writable memory); moving moves the storage; resize() on adopted memory first copies
// it into an owned vector. No I/O here (kernels/ is pure compute): the owner handle is opaque.
// Thread-safety: like std::vector (concurrent reads are safe).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <new>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace meshless {

class SampleBytes {
public:
    SampleBytes() = default;
    /// n zero bytes, owned.
    explicit SampleBytes(std::size_t n) : vec_(n) {}
    /// Takes ownership of the vector's bytes (implicit, so `v.bytes = std::move(vec)` reads naturally).
    SampleBytes(std::vector<std::byte>&& v) noexcept : vec_(std::move(v)) {}  // NOLINT(google-explicit-constructor)
    SampleBytes(const std::vector<std::byte>& v) : vec_(v) {}                  // NOLINT(google-explicit-constructor)

    /// Adopts n writable bytes at p, kept alive by `owner` (released when the last SampleBytes
    /// holding it goes). `p` must stay valid and writable while `owner` lives.
    static SampleBytes adopt(std::byte* p, std::size_t n, std::shared_ptr<void> owner) {
        SampleBytes b;
        b.ext_ = p;
        b.ext_size_ = n;
        b.owner_ = std::move(owner);
        return b;
    }

    /// n zero bytes that become resident only as they are written: calloc's large blocks are
    /// fresh anonymous pages, so a decoder that fills them from a stream grows its memory as the
    /// data arrives, not by what a header claims (decompression bombs). std::bad_alloc
    /// when the address space cannot be had.
    static SampleBytes lazy_zeroed(std::size_t n) {
        if (n == 0) return SampleBytes();
        void* p = std::calloc(n, 1);
        if (!p) throw std::bad_alloc();
        return adopt(static_cast<std::byte*>(p), n, std::shared_ptr<void>(p, std::free));
    }

    SampleBytes(const SampleBytes& o) : vec_(o.begin(), o.end()) {}
    SampleBytes& operator=(const SampleBytes& o) {
        if (this != &o) *this = SampleBytes(o);
        return *this;
    }
    SampleBytes(SampleBytes&& o) noexcept { swap(o); }
    SampleBytes& operator=(SampleBytes&& o) noexcept {
        SampleBytes tmp(std::move(o));
        swap(tmp);
        return *this;
    }
    ~SampleBytes() = default;

    /// True when the bytes are adopted (e.g. a file mapping) rather than an owned vector.
    bool adopted() const { return owner_ != nullptr; }

    std::byte* data() { return owner_ ? ext_ : vec_.data(); }
    const std::byte* data() const { return owner_ ? ext_ : vec_.data(); }
    std::size_t size() const { return owner_ ? ext_size_ : vec_.size(); }
    bool empty() const { return size() == 0; }
    std::byte* begin() { return data(); }
    std::byte* end() { return data() + size(); }
    const std::byte* begin() const { return data(); }
    const std::byte* end() const { return data() + size(); }
    std::byte& operator[](std::size_t i) { return data()[i]; }
    const std::byte& operator[](std::size_t i) const { return data()[i]; }
    operator std::span<const std::byte>() const { return {data(), size()}; }  // NOLINT(google-explicit-constructor)
    operator std::span<std::byte>() { return {data(), size()}; }              // NOLINT(google-explicit-constructor)

    /// Resizes like std::vector (new bytes are zero); adopted bytes are first copied into a vector.
    void resize(std::size_t n) {
        if (owner_) to_owned();
        vec_.resize(n);
    }
    void clear() { *this = SampleBytes(); }

    friend bool operator==(const SampleBytes& a, const SampleBytes& b) {
        return a.size() == b.size() && (a.size() == 0 || std::memcmp(a.data(), b.data(), a.size()) == 0);
    }

private:
    void swap(SampleBytes& o) noexcept {
        vec_.swap(o.vec_);
        std::swap(ext_, o.ext_);
        std::swap(ext_size_, o.ext_size_);
        owner_.swap(o.owner_);
    }
    void to_owned() {
        std::vector<std::byte> v(begin(), end());
        owner_.reset();
        ext_ = nullptr;
        ext_size_ = 0;
        vec_ = std::move(v);
    }

    std::vector<std::byte> vec_;
    std::byte* ext_ = nullptr;
    std::size_t ext_size_ = 0;
    std::shared_ptr<void> owner_;
};

}  // namespace meshless
