// Platform ceilings: see platform_ceiling.hpp.
#include "bench/platform_ceiling.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "kernels/errors.hpp"
#include "stream/zeroed_buffer.hpp"

namespace meshless::bench {

namespace {

constexpr std::size_t kPiece = std::size_t{1} << 20;

/// Best wall seconds of `reps` runs of work(0, 1) on one thread and of work(0, 2) || work(1, 2) on two.
Scaling best_of(int reps, std::size_t bytes, const std::function<void(int part, int parts)>& work) {
    Scaling s;
    s.bytes = bytes;
    s.one_s = s.two_s = 1e30;
    for (int r = 0; r < std::max(reps, 1); ++r) {
        for (int threads = 1; threads <= 2; ++threads) {
            const auto t0 = std::chrono::steady_clock::now();  // (a thread's start, microseconds, is in the timing)
            if (threads == 1) {
                work(0, 1);
            } else {
                std::exception_ptr failed;
                std::thread other([&] {
                    try {
                        work(1, 2);
                    } catch (...) {
                        failed = std::current_exception();
                    }
                });
                try {
                    work(0, 2);
                } catch (...) {
                    other.join();
                    throw;
                }
                other.join();
                if (failed) std::rethrow_exception(failed);
            }
            const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            double& best = threads == 1 ? s.one_s : s.two_s;
            best = std::min(best, sec);
        }
    }
    return s;
}

/// [first, end) of part `part` of `parts` equal parts of n, in whole pieces of `align`.
std::pair<std::size_t, std::size_t> part_range(std::size_t n, int part, int parts, std::size_t align) {
    const std::size_t pieces = (n + align - 1) / align;
    const std::size_t per = (pieces + static_cast<std::size_t>(parts) - 1) / static_cast<std::size_t>(parts);
    const std::size_t first = std::min(n, per * align * static_cast<std::size_t>(part));
    return {first, std::min(n, first + per * align)};
}

}  // namespace

Scaling page_cache_read(const std::filesystem::path& file, int reps) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw IoError(file.string() + ": cannot open: " + std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    const off_t end = ::lseek(fd, 0, SEEK_END);
    if (end < 0) throw IoError(file.string() + ": cannot seek: " + std::strerror(errno));
    const auto size = static_cast<std::size_t>(end);
    auto read_part = [&](int part, int parts) {
        const auto [first, last] = part_range(size, part, parts, kPiece);
        const std::unique_ptr<char[]> buf(new char[kPiece]);
        for (std::size_t at = first; at < last;) {
            const ssize_t got = ::pread(fd, buf.get(), std::min(kPiece, last - at), static_cast<off_t>(at));
            if (got <= 0) {
                if (got < 0 && errno == EINTR) continue;
                throw IoError(file.string() + ": cannot read at offset " + std::to_string(at));
            }
            at += static_cast<std::size_t>(got);
        }
    };
    read_part(0, 1);  // into the page cache
    return best_of(reps, size, read_part);
}

Scaling memory_copy(std::size_t bytes, int reps) {
    std::vector<char> a(bytes, 1), b(bytes, 2);  // faulted in here, outside the timing
    return best_of(reps, bytes, [&](int part, int parts) {
        const auto [first, last] = part_range(bytes, part, parts, 4096);
        std::memcpy(b.data() + first, a.data() + first, last - first);
    });
}

Scaling fresh_memory(std::size_t bytes, int reps) {
    return best_of(reps, bytes, [&](int part, int parts) {
        const auto [first, last] = part_range(bytes, part, parts, 4096);
        ZeroedBuffer<char> fresh(last - first);  // as the splat sink's accumulators: huge pages advised
        std::memset(fresh.data(), 1, fresh.size());  // the one write that faults every page in
        volatile char seen = fresh.data()[fresh.size() / 2];  // (kept: the writes cannot be elided)
        (void)seen;
    });
}

}  // namespace meshless::bench
