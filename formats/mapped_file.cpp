#include "formats/mapped_file.hpp"
#include "formats/binary_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

struct Mapping {
    void* base = MAP_FAILED;
    std::size_t length = 0;
    ~Mapping() {
        if (base != MAP_FAILED) ::munmap(base, length);
    }
};

struct Fd {
    int fd = -1;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

SampleBytes map_file_range(const std::string& path, std::uint64_t offset, std::uint64_t count) {
    require_regular_file(path);
    Fd f;
    f.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (f.fd < 0) throw IoError(path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(f.fd, &st) != 0) throw IoError(path + ": cannot stat: " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw IoError(path + ": not a regular file, cannot be mapped");
    const auto size = static_cast<std::uint64_t>(st.st_size);
    if (offset > size || count > size - offset)
        throw FormatError(path + ": truncated: need " + std::to_string(count) + " bytes at offset " +
                          std::to_string(offset) + ", file has " + std::to_string(size));
    if (count == 0) return SampleBytes();
    const auto page = static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
    const std::uint64_t start = offset - offset % page, skip = offset - start;
    auto m = std::make_shared<Mapping>();
    m->length = static_cast<std::size_t>(skip + count);
    // private + writable without MAP_POPULATE: read faults map page-cache pages (nothing copied);
    // only pages a caller writes get copied
    m->base = ::mmap(nullptr, m->length, PROT_READ | PROT_WRITE, MAP_PRIVATE, f.fd, static_cast<off_t>(start));
    if (m->base == MAP_FAILED) throw IoError(path + ": cannot map: " + std::strerror(errno));
    ::madvise(m->base, m->length, MADV_WILLNEED);  // start readahead of what is not cached yet
    auto* p = static_cast<std::byte*>(m->base) + skip;
    return SampleBytes::adopt(p, static_cast<std::size_t>(count), std::move(m));
}

}  // namespace meshless
