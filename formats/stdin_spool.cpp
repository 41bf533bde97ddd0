#include "formats/stdin_spool.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "formats/temporary_files.hpp"
#include "kernels/errors.hpp"

namespace meshless {

StdinSpool::StdinSpool() {
    if (::isatty(0) == 1) throw IoError("-: standard input is a terminal; pipe a volume in (e.g. < vol.nrrd)");
    std::string name;
    file_ = unlinked_temporary("stdin", name);  // nothing stays behind, whatever ends the process
    fd_ = ::fileno(file_);
    path_ = "/proc/self/fd/" + std::to_string(fd_);
    std::vector<char> buf(1 << 20);
    for (;;) {
        const ssize_t n = ::read(0, buf.data(), buf.size());
        if (n == 0) break;
        if (n < 0) {
            if (errno == EINTR) continue;
            const int e = errno;
            std::fclose(file_);
            throw IoError("-: cannot read standard input: " + std::string(std::strerror(e)));
        }
        for (ssize_t done = 0; done < n;) {
            const ssize_t w = ::write(fd_, buf.data() + done, static_cast<std::size_t>(n - done));
            if (w < 0 && errno == EINTR) continue;
            if (w < 0) {
                const int e = errno;
                std::fclose(file_);
                throw IoError("-: cannot spool standard input to a temporary file: " + std::string(std::strerror(e)));
            }
            done += w;
        }
    }
}

StdinSpool::~StdinSpool() {
    if (file_) std::fclose(file_);
}

void StdinSpool::rethrow_renamed() const {
    auto renamed = [&](std::string m) {
        // a header naming a separate data file (MetaImage ElementDataFile, detached NRRD) resolves
        // it beside the spool (/proc/self/fd/), where it never is: say so instead of naming that
        // made-up path (any name there but the spool's own, "3d.raw" beside fd 3 included)
        const std::string dir = path_.substr(0, path_.find_last_of('/') + 1);
        auto delimiter = [&](std::size_t i) { return i >= m.size() || m[i] == ':' || m[i] == ' ' || m[i] == '\''; };
        for (std::size_t at = m.find(dir); at != std::string::npos; at = m.find(dir, at + 1)) {
            std::size_t end = at + dir.size();
            while (!delimiter(end)) ++end;
            if (m.compare(at, end - at, path_) == 0) continue;  // the spool itself
            return "- (stdin): the header names a separate data file '" + m.substr(at + dir.size(), end - at - dir.size()) +
                   "', which cannot be found from standard input: give the header's path instead of -";
        }
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

}  // namespace meshless
