#include "stream/footprint_spool.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "formats/temporary_files.hpp"
#include "kernels/errors.hpp"

namespace meshless {

std::size_t SpoolMemory::take(std::size_t want, std::size_t least) {
    std::size_t left = left_.load(std::memory_order_relaxed);
    for (;;) {
        const std::size_t got = std::min(want, left);
        if (got < least || got == 0) return 0;
        if (left_.compare_exchange_weak(left, left - got, std::memory_order_relaxed)) return got;
    }
}

FootprintSpool::FootprintSpool(const std::string& purpose, std::shared_ptr<SpoolMemory> memory)
    : sealed_(!memory), memory_(std::move(memory)) {
    f_ = unlinked_temporary(purpose, name_);
}

FootprintSpool::~FootprintSpool() {
    if (f_) std::fclose(f_);
}

void FootprintSpool::fail(const char* what, int err) const {
    throw IoError(name_ + ": cannot " + what + " the splat footprint spool (deleted temporary file): " +
                  (err ? std::strerror(err) : "short file"));
}

void FootprintSpool::append(std::span<const EwaFootprint> footprints) {
    // the memory tier first, chunk by chunk, while the budget grants them; only the memory part
    // precedes the file part, so the tier stops for good at the first chunk it cannot fill whole
    while (!footprints.empty() && (count_ < memory_capacity_ || !sealed_)) {
        if (count_ == memory_capacity_) {
            // the file has taken nothing yet (sealed_ is false): ask for the next chunk
            const std::size_t got = memory_->take(kChunk * sizeof(EwaFootprint), sizeof(EwaFootprint));
            const std::size_t n = got / sizeof(EwaFootprint);
            if (n == 0) {
                sealed_ = true;
                break;
            }
            if (n < kChunk) sealed_ = true;  // a short chunk can only be the last one (indexing by kChunk)
            chunks_.emplace_back();
            chunks_.back().reserve(n);
            memory_capacity_ += n;
        }
        LargeBuffer<EwaFootprint>& c = chunks_.back();
        const std::size_t n = static_cast<std::size_t>(
            std::min<std::uint64_t>(footprints.size(), memory_capacity_ - count_));
        c.insert(c.end(), footprints.begin(), footprints.begin() + static_cast<std::ptrdiff_t>(n));
        footprints = footprints.subspan(n);
        count_ += n;
    }
    if (footprints.empty()) return;
    errno = 0;
    if (std::fwrite(footprints.data(), sizeof(EwaFootprint), footprints.size(), f_) != footprints.size())
        fail("write to", errno);
    count_ += footprints.size();
}

void FootprintSpool::flush() {
    errno = 0;
    if (std::fflush(f_) != 0) fail("write to", errno);
}

void FootprintSpool::check_range(std::uint64_t first, std::uint64_t count) const {
    if (first > count_ || count > count_ - first)
        throw IoError(name_ + ": cannot read footprints " + std::to_string(first) + ".." + std::to_string(first + count) +
                      " back from the splat footprint spool (deleted temporary file): it holds " + std::to_string(count_));
}

void FootprintSpool::read(std::uint64_t first, std::span<EwaFootprint> out) const {
    std::vector<EwaFootprint> scratch;
    std::size_t at = 0;
    visit(first, out.size(), scratch, [&](std::span<const EwaFootprint> part) {
        std::copy(part.begin(), part.end(), out.begin() + static_cast<std::ptrdiff_t>(at));
        at += part.size();
    });
}

void FootprintSpool::read_file(std::uint64_t first, std::span<EwaFootprint> out) const {
    const int fd = ::fileno(f_);
    char* dst = reinterpret_cast<char*>(out.data());
    const std::size_t want = out.size() * sizeof(EwaFootprint);
    const std::uint64_t offset = first * sizeof(EwaFootprint);
    std::size_t got = 0;
    while (got < want) {
        const ssize_t r = ::pread(fd, dst + got, want - got, static_cast<off_t>(offset + got));
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) fail("read back from", r < 0 ? errno : 0);
        got += static_cast<std::size_t>(r);
    }
}

}  // namespace meshless
