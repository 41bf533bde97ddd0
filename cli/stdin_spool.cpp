#include "cli/stdin_spool.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "kernels/errors.hpp"

namespace meshless::cli {

StdinSpool::StdinSpool() {
    if (::isatty(0) == 1) throw IoError("-: standard input is a terminal; pipe a volume in (e.g. < vol.nrrd)");
    const char* dir = std::getenv("TMPDIR");
    std::string tmpl = std::string(dir && *dir ? dir : "/tmp") + "/meshless-stdin-XXXXXX";
    std::vector<char> name(tmpl.begin(), tmpl.end());
    name.push_back('\0');
    fd_ = ::mkstemp(name.data());
    if (fd_ < 0) throw IoError("-: cannot make a temporary file in " + tmpl.substr(0, tmpl.rfind('/')) + ": " + std::strerror(errno));
    ::unlink(name.data());  // nothing stays behind, whatever ends the process
    path_ = "/proc/self/fd/" + std::to_string(fd_);
    std::vector<char> buf(1 << 20);
    for (;;) {
        const ssize_t n = ::read(0, buf.data(), buf.size());
        if (n == 0) break;
        if (n < 0) {
            if (errno == EINTR) continue;
            const int e = errno;
            ::close(fd_);
            throw IoError("-: cannot read standard input: " + std::string(std::strerror(e)));
        }
        for (ssize_t done = 0; done < n;) {
            const ssize_t w = ::write(fd_, buf.data() + done, static_cast<std::size_t>(n - done));
            if (w < 0 && errno == EINTR) continue;
            if (w < 0) {
                const int e = errno;
                ::close(fd_);
                throw IoError("-: cannot spool standard input to a temporary file: " + std::string(std::strerror(e)));
            }
            done += w;
        }
    }
}

StdinSpool::~StdinSpool() {
    if (fd_ >= 0) ::close(fd_);
}

void StdinSpool::rethrow_renamed() const {
    auto renamed = [&](std::string m) {
        for (std::size_t at; (at = m.find(path_)) != std::string::npos;) m.replace(at, path_.size(), "- (stdin)");
        return m;
    };
    try {
        throw;
    } catch (const FormatError& e) {
        throw FormatError(renamed(e.what()));
    } catch (const IoError& e) {
        throw IoError(renamed(e.what()));
    } catch (const InvalidArgument& e) {
        throw InvalidArgument(renamed(e.what()));
    }
}

}  // namespace meshless::cli
