#include "array_slices.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>

#include "kernels/errors.hpp"

namespace meshless::python {

namespace {
std::uintptr_t page_size() { return static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE)); }
}  // namespace

ArraySlices::ArraySlices(const VolumeView& view, bool release_pages)
    : view_(view),
      release_(release_pages),
      slice_bytes_(static_cast<std::size_t>(view.grid.dims[0] * view.grid.dims[1]) * sample_size(view.type)) {
    const auto base = reinterpret_cast<std::uintptr_t>(view.data), page = page_size();
    released_ = reinterpret_cast<const std::byte*>((base + page - 1) / page * page);  // whole pages of the volume only
}

void ArraySlices::read_slices(std::int64_t k, std::int64_t count, std::byte* out) {
    if (k < 0 || count < 0 || k + count > view_.grid.dims[2]) throw InvalidArgument("volume: slices out of range");
    const auto* base = static_cast<const std::byte*>(view_.data);
    std::memcpy(out, base + static_cast<std::size_t>(k) * slice_bytes_, static_cast<std::size_t>(count) * slice_bytes_);
    if (!release_) return;
    // the slices below k are done (reads go forward): their whole pages go back to the file
    const auto page = page_size();
    const auto end = reinterpret_cast<std::uintptr_t>(base + static_cast<std::size_t>(k) * slice_bytes_) / page * page;
    const auto from = reinterpret_cast<std::uintptr_t>(released_);
    if (end > from) {
        madvise(reinterpret_cast<void*>(from), end - from, MADV_DONTNEED);  // advice: a failure only keeps the pages
        released_ = reinterpret_cast<const std::byte*>(end);
    }
}

}  // namespace meshless::python
