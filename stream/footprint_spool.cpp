#include "stream/footprint_spool.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "formats/temporary_files.hpp"
#include "kernels/errors.hpp"

namespace meshless {

FootprintSpool::FootprintSpool(const std::string& purpose) { f_ = unlinked_temporary(purpose, name_); }

FootprintSpool::~FootprintSpool() {
    if (f_) std::fclose(f_);
}

void FootprintSpool::fail(const char* what, int err) const {
    throw IoError(name_ + ": cannot " + what + " the splat footprint spool (deleted temporary file): " +
                  (err ? std::strerror(err) : "short file"));
}

void FootprintSpool::append(std::span<const EwaFootprint> footprints) {
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

void FootprintSpool::read(std::uint64_t first, std::span<EwaFootprint> out) const {
    if (first + out.size() > count_)
        throw IoError(name_ + ": cannot read footprints " + std::to_string(first) + ".." + std::to_string(first + out.size()) +
                      " back from the splat footprint spool (deleted temporary file): it holds " + std::to_string(count_));
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
