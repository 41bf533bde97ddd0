#include "ooc/brick_store_identity.hpp"
#include "formats/binary_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "kernels/errors.hpp"
#include "ooc/brick_store.hpp"

namespace meshless {

BrickStoreIdentity brick_store_identity(const std::string& path) {
    require_regular_file(path);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat sb {};
    if (::fstat(fd, &sb) != 0) throw IoError(path + ": cannot stat (" + std::strerror(errno) + ")");
    BrickStoreIdentity id;
    id.file_bytes = static_cast<std::uint64_t>(sb.st_size);
    unsigned char h[kBrickStoreHeaderBytes], f[kBrickStoreFooterBytes];
    if (id.file_bytes < sizeof h + sizeof f || ::pread(fd, h, sizeof h, 0) != static_cast<ssize_t>(sizeof h) ||
        ::pread(fd, f, sizeof f, static_cast<off_t>(id.file_bytes - sizeof f)) != static_cast<ssize_t>(sizeof f) ||
        std::memcmp(h, kBrickStoreMagic, 8) != 0 || std::memcmp(f + 24, kBrickStoreEndMagic, 8) != 0)
        throw FormatError(path + ": not a complete meshless brick store");
    std::memcpy(&id.header_crc, h + 252, 4);
    std::memcpy(&id.index_crc, f + 16, 4);
    std::memcpy(&id.brick_count, f + 8, 8);
    return id;
}

}  // namespace meshless
